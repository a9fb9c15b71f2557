"""Reading user files with a size cap: ``/dev/zero``, FIFOs and huge files fail fast.

Never ``Path.read_text()`` (or ``open``, ``np.loadtxt``, ...) on a path a user
gave: a character device or a FIFO has no size and would be read (or waited
on) forever.  `read_text_file` opens without blocking, accepts regular files
only, checks the size before reading and reads at most one byte more than the
cap.  `open_text_file` does the same for a file read as a stream of lines (a
large log), so that memory stays bounded by what the caller keeps, not by the
size of the file.  A test (``tests/files/test_textfile.py``) scans the source
for any other read of a file outside this package.
"""

from __future__ import annotations

import errno
import io
import os
import stat
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TextIO

from ..errors import FileFormatError
from .limits import MAX_TEXT_FILE_BYTES

__all__ = ["check_input_file", "open_text_file", "read_text_file"]


def _kind(mode: int) -> str:
    if stat.S_ISDIR(mode):
        return "a directory"
    if stat.S_ISFIFO(mode):
        return "a pipe (FIFO)"
    if stat.S_ISCHR(mode):
        return "a character device"
    if stat.S_ISBLK(mode):
        return "a block device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "not a regular file"


def _check_stat(p: Path, st: os.stat_result, max_bytes: int | None, what: str) -> None:
    if not stat.S_ISREG(st.st_mode):
        raise FileFormatError(f"{p}: is {_kind(st.st_mode)}, not a {what}")
    if max_bytes is not None and st.st_size > max_bytes:
        raise FileFormatError(
            f"{p}: {st.st_size:,} bytes is larger than the limit of {max_bytes:,} bytes "
            f"for a {what}"
        )


def _os_error(p: Path, exc: OSError) -> OSError:
    """The same error with the path and the reason only (no ``[Errno N]``)."""
    code = exc.errno or errno.EIO
    return type(exc)(code, exc.strerror or os.strerror(code), str(p))


def check_input_file(
    path: str | os.PathLike[str], *, max_bytes: int | None = MAX_TEXT_FILE_BYTES, what: str = "file"
) -> Path:
    """Raise unless ``path`` is an existing regular file of at most ``max_bytes``.

    ``max_bytes=None`` checks the kind only, for a file that its reader
    streams with bounded memory (a Parquet or CSV sweep output read by pyarrow).

    Raises
    ------
    FileFormatError
        For a directory, device, FIFO or socket, or a file over the size cap.
    OSError
        When the file does not exist or cannot be examined.
    """
    p = Path(path)
    try:
        st = p.stat()
    except OSError as exc:
        raise _os_error(p, exc) from None
    _check_stat(p, st, max_bytes, what)
    return p


def _open_checked(p: Path, max_bytes: int, what: str) -> int:
    """A descriptor of the regular file ``p`` of at most ``max_bytes``, opened without waiting."""
    try:
        # O_NONBLOCK: opening a FIFO without a writer must not wait
        fd = os.open(p, os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC)
    except OSError as exc:
        raise _os_error(p, exc) from None
    try:
        _check_stat(p, os.fstat(fd), max_bytes, what)
    except BaseException:
        os.close(fd)
        raise
    return fd


class _CappedReader(io.RawIOBase):
    """Raw reads of a descriptor that fail once more than ``max_bytes`` came (a growing file)."""

    def __init__(self, fd: int, p: Path, max_bytes: int, what: str) -> None:
        super().__init__()
        self._fd, self._path, self._left, self._max, self._what = fd, p, max_bytes, max_bytes, what

    def readable(self) -> bool:
        return True

    def readinto(self, buffer: memoryview) -> int:  # type: ignore[override]
        try:
            n = os.readv(self._fd, [buffer])
        except OSError as exc:
            raise _os_error(self._path, exc) from None
        self._left -= n
        if self._left < 0:
            raise FileFormatError(
                f"{self._path}: larger than the limit of {self._max:,} bytes for a {self._what}"
            )
        return n

    def close(self) -> None:
        if not self.closed:
            os.close(self._fd)
        super().close()


@contextmanager
def open_text_file(
    path: str | os.PathLike[str], *, max_bytes: int = MAX_TEXT_FILE_BYTES, what: str = "file"
) -> Iterator[TextIO]:
    """The UTF-8 text of a regular file of at most ``max_bytes``, as a stream (bounded memory).

    The same checks as `read_text_file`, before the first byte is read; the
    stream keeps universal newlines off (``newline=""``, as the ``csv`` module
    wants) and buffers 64 KiB at a time.

    Raises
    ------
    FileFormatError
        For a directory, device, FIFO or socket, a file over the size cap (also
        one that grows past it while being read), or text that is not UTF-8.
    OSError
        When the file does not exist or cannot be read (the message has no ``[Errno N]``).

    Examples
    --------
    >>> with open_text_file("/dev/zero") as fh:
    ...     fh.read()
    Traceback (most recent call last):
    ...
    seapass.errors.FileFormatError: /dev/zero: is a character device, not a file
    """
    p = Path(path)
    raw = _CappedReader(_open_checked(p, max_bytes, what), p, max_bytes, what)
    stream = io.TextIOWrapper(io.BufferedReader(raw, 1 << 16), encoding="utf-8", newline="")
    try:
        yield stream
    except UnicodeDecodeError:
        raise FileFormatError(f"{p}: not a UTF-8 text file") from None
    finally:
        stream.close()


def read_text_file(
    path: str | os.PathLike[str], *, max_bytes: int = MAX_TEXT_FILE_BYTES, what: str = "file"
) -> str:
    """The UTF-8 text of a regular file of at most ``max_bytes``.

    Raises
    ------
    FileFormatError
        For a directory, device, FIFO or socket, a file over the size cap, or
        text that is not UTF-8.
    OSError
        When the file does not exist or cannot be read (the message has no ``[Errno N]``).

    Examples
    --------
    >>> read_text_file("/dev/zero")
    Traceback (most recent call last):
    ...
    seapass.errors.FileFormatError: /dev/zero: is a character device, not a file
    """
    p = Path(path)
    fd = _open_checked(p, max_bytes, what)
    try:
        chunks: list[bytes] = []
        left = max_bytes + 1
        while left > 0:
            chunk = os.read(fd, min(left, 1 << 16))
            if not chunk:
                break
            chunks.append(chunk)
            left -= len(chunk)
    except OSError as exc:
        raise _os_error(p, exc) from None
    finally:
        os.close(fd)
    data = b"".join(chunks)
    if len(data) > max_bytes:  # grew while being read
        raise FileFormatError(f"{p}: larger than the limit of {max_bytes:,} bytes for a {what}")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise FileFormatError(
            f"{p}: not a UTF-8 text file (byte {exc.start} cannot be decoded)"
        ) from None
