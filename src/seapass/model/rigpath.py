"""The ``[rig]`` table of a design file: the paper's preset or the checked path of a rig file."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

from ..errors import FileFormatError
from ..files.limits import MAX_TEXT_FILE_BYTES
from ..files.textfile import check_input_file

__all__ = ["rig_file_path"]


def rig_file_path(rig: Mapping[str, str], base_dir: Path) -> str:
    """``"paper"`` or the checked path of a rig file (read later)."""
    if ("file" in rig) == ("preset" in rig):
        raise FileFormatError("rig: give exactly one of rig.file and rig.preset")
    if "preset" in rig:
        return "paper"
    path = Path(rig["file"])
    full = path if path.is_absolute() else base_dir / path
    try:  # a rig file is read later: refuse a device, a FIFO or a huge file now
        check_input_file(full, max_bytes=MAX_TEXT_FILE_BYTES, what="rig file")
    except OSError as exc:
        raise FileFormatError(f"rig.file: {full}: {exc.strerror}") from None
    except FileFormatError as exc:
        raise FileFormatError(f"rig.file: {exc}") from None
    return str(full)
