"""Files in and out: atomic writes and the strict TOML loader.

What lives here: [`limits`][seapass.files.limits] (every size limit of seapass:
files, arrays, step counts, expressions, text), [`textfile`][seapass.files.textfile]
(read a user's file with a size cap: devices, FIFOs and huge files fail fast),
[`atomic`][seapass.files.atomic] (write a file or a directory so that an
interrupted run never leaves a half-written one), [`owned`][seapass.files.owned]
(the one rule of every output: never replace a file seapass did not write, unless
forced; the manifest of what seapass wrote), [`toml`][seapass.files.toml]
(read design and rig files; every error names the file; write the flat tables
seapass writes back), [`schema`][seapass.files.schema] (the declarative checker of
design and rig files: a `Field` per key), [`jsontext`][seapass.files.jsontext] (strict
JSON text of any result: non-finite numbers null, numpy values plain) and
[`csvtext`][seapass.files.csvtext] (CSV text of result rows).

May import: [`seapass.errors`][seapass.errors] and `seapass.version`.
"""

from .atomic import atomic_save, atomic_write, atomic_write_text
from .toml import dump_toml, load_toml_file

__all__ = ["atomic_save", "atomic_write", "atomic_write_text", "dump_toml", "load_toml_file"]
