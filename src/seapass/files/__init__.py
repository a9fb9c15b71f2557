"""Files in and out: atomic writes and the strict TOML loader.

What lives here: :mod:`~seapass.files.atomic` (write a file or a directory so
that an interrupted run never leaves a half-written one) and
:mod:`~seapass.files.toml` (read design and rig files; every error names the
file).

May import: :mod:`seapass.errors` only.
"""

from .atomic import atomic_save, atomic_write, atomic_write_text
from .toml import load_toml_file

__all__ = ["atomic_save", "atomic_write", "atomic_write_text", "load_toml_file"]
