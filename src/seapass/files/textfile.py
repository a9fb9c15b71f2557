"""Reading user files with a size cap: ``/dev/zero``, FIFOs and huge files fail fast.

Never ``Path.read_text()`` on a path a user gave: a character device or a FIFO
has no size and would be read (or waited on) forever.  `read_text_file` opens
without blocking, accepts regular files only, checks the size before reading
and reads at most one byte more than the cap.
"""

from __future__ import annotations

import errno
import os
import stat
from pathlib import Path

from ..errors import FileFormatError
from .limits import MAX_TEXT_FILE_BYTES

__all__ = ["check_input_file", "read_text_file"]


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


def _check_stat(p: Path, st: os.stat_result, max_bytes: int, what: str) -> None:
    if not stat.S_ISREG(st.st_mode):
        raise FileFormatError(f"{p}: is {_kind(st.st_mode)}, not a {what}")
    if st.st_size > max_bytes:
        raise FileFormatError(
            f"{p}: {st.st_size:,} bytes is larger than the limit of {max_bytes:,} bytes "
            f"for a {what}"
        )


def _os_error(p: Path, exc: OSError) -> OSError:
    """The same error with the path and the reason only (no ``[Errno N]``)."""
    code = exc.errno or errno.EIO
    return type(exc)(code, exc.strerror or os.strerror(code), str(p))


def check_input_file(
    path: str | os.PathLike[str], *, max_bytes: int = MAX_TEXT_FILE_BYTES, what: str = "file"
) -> Path:
    """Raise unless ``path`` is an existing regular file of at most ``max_bytes``.

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
    try:
        # O_NONBLOCK: opening a FIFO without a writer must not wait
        fd = os.open(p, os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC)
    except OSError as exc:
        raise _os_error(p, exc) from None
    try:
        _check_stat(p, os.fstat(fd), max_bytes, what)
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
