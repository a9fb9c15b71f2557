"""The house rules of the package layout, checked on the source (see docs/architecture.md).

* imports point one way: a subpackage imports only from its own package and from
  the layers below it (:data:`LAYERS`), at module level and inside functions; the one
  exception is a result's ``.plot()`` method, which may import :mod:`seapass.plot`
  inside its body (the convenience python-control offers too: the result only hands
  itself to the plot layer, and computing stays separate from drawing);
* no module imports a private name (``_x``) from another module;
* no module is longer than 500 lines, and none is named ``*_core``/``*_extra``/``*_misc``;
* every subpackage says in its docstring what lives there and what it may import;
* ``import seapass`` loads none of the heavy scientific libraries.
"""

from __future__ import annotations

import ast
import re
import subprocess
import sys
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "seapass"

#: Bottom to top.  A package may import from its own layer group only where listed together.
LAYERS: tuple[tuple[str, ...], ...] = (
    ("errors", "version", "outcome", "lazy"),
    ("progress",),  # imports errors only: the bottom group imports nothing of its own
    ("files",),
    ("exact",),
    ("model",),
    ("analysis",),
    ("ports",),
    ("delay",),
    ("sim",),
    ("batch",),
    ("sampled",),
    ("robust",),
    ("tuning",),
    ("rig",),
    ("export",),
    ("sweep",),
    ("paper",),
    ("plot",),
    ("report",),
    ("explore",),
    ("cli",),
)
RANK = {name: i for i, group in enumerate(LAYERS) for name in group}


def _modules() -> list[Path]:
    return sorted(p for p in SRC.rglob("*.py") if "__pycache__" not in p.parts)


def _dotted(path: Path) -> list[str]:
    parts = list(path.relative_to(SRC.parent).with_suffix("").parts)
    return parts[:-1] if parts[-1] == "__init__" else parts


def _imports(path: Path) -> list[tuple[int, str, list[str]]]:
    """``(line, absolute module, imported names)`` of every import in ``path``."""
    return [(line, module, names) for line, module, names, _f in _imports_in_functions(path)]


def _imports_in_functions(path: Path) -> list[tuple[int, str, list[str], str]]:
    """`_imports` plus the name of the innermost enclosing function (``""`` at module level)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    here = _dotted(path)
    package = here if path.name == "__init__.py" else here[:-1]
    out = []

    def visit(node: ast.AST, func: str) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef):
                visit(child, child.name)
                continue
            if isinstance(child, ast.Import):
                out.extend((child.lineno, a.name, [], func) for a in child.names)
            elif isinstance(child, ast.ImportFrom):
                if child.level:
                    base = package[: len(package) - child.level + 1]
                    module = ".".join(base + ([child.module] if child.module else []))
                else:
                    module = child.module or ""
                out.append((child.lineno, module, [a.name for a in child.names], func))
            visit(child, func)

    visit(tree, "")
    return out


def _layer_of(dotted: list[str]) -> str | None:
    """The layered unit of a seapass module: its subpackage, or a top-level module."""
    if len(dotted) < 2:
        return None  # seapass/__init__.py: the lazy front door, checked separately
    return dotted[1]


def test_layers_cover_every_subpackage_and_top_level_module() -> None:
    units = {p.name for p in SRC.iterdir() if p.is_dir() and (p / "__init__.py").exists()}
    units |= {p.stem for p in SRC.glob("*.py") if p.stem != "__init__"}
    assert units <= set(RANK), f"add {sorted(units - set(RANK))} to LAYERS and the docs"


@pytest.mark.parametrize("path", _modules(), ids=lambda p: str(p.relative_to(SRC)))
def test_imports_point_down(path: Path) -> None:
    unit = _layer_of(_dotted(path))
    if unit is None:
        return
    bad = []
    for line, module, _names, func in _imports_in_functions(path):
        parts = module.split(".")
        if parts[0] != "seapass" or len(parts) < 2:
            continue
        target = parts[1]
        if target == "plot" and func == "plot":
            continue  # a result's .plot() hands itself to the plot layer
        if target != unit and RANK[target] >= RANK[unit]:
            bad.append(f"line {line}: {module} (layer {target} is not below {unit})")
    assert not bad, "\n".join(bad)


@pytest.mark.parametrize("path", _modules(), ids=lambda p: str(p.relative_to(SRC)))
def test_no_private_imports_across_modules(path: Path) -> None:
    bad = [
        f"line {line}: {name} from {module}"
        for line, module, names in _imports(path)
        if module.startswith("seapass")
        for name in names
        if name.startswith("_") and not name.startswith("__")
    ]
    assert not bad, "\n".join(bad)


@pytest.mark.parametrize("path", _modules(), ids=lambda p: str(p.relative_to(SRC)))
def test_module_size_and_name(path: Path) -> None:
    lines = path.read_text(encoding="utf-8").count("\n")
    assert lines <= 500, f"{lines} lines: split it by concept"
    assert not path.stem.endswith(("_core", "_extra", "_misc")), "name modules by what they hold"


def test_every_subpackage_states_its_contents_and_imports() -> None:
    import importlib

    for init in sorted(SRC.glob("*/__init__.py")):
        mod = importlib.import_module(f"seapass.{init.parent.name}")
        doc = mod.__doc__ or ""
        assert "What lives here" in doc, init
        if init.parent.name != "cli":
            assert "May import" in doc, init


def _used_layers(package: Path) -> set[str]:
    """The layered units a subpackage imports (outside itself), as the layer test sees them."""
    unit = package.name
    used = set()
    for path in sorted(package.rglob("*.py")):
        for _line, module, _names, func in _imports_in_functions(path):
            parts = module.split(".")
            if parts[0] != "seapass" or len(parts) < 2 or parts[1] == unit:
                continue
            if parts[1] == "plot" and func == "plot":
                continue  # a result's .plot() hands itself to the plot layer
            used.add(parts[1])
    return used


def _may_import(doc: str) -> tuple[set[str], str | None]:
    """The units a docstring's "May import:" sentence names, and X of "everything in X and below"."""
    start = doc.index("May import:") + len("May import:")
    end = re.search(r"\.(\s|$)", doc[start:])
    sentence = doc[start : start + end.start()] if end else doc[start:]
    named = set(re.findall(r"`seapass\.(\w+)", sentence))
    below = re.search(r"everything in \[?`seapass\.(\w+)`", sentence)
    return named, below.group(1) if below and "and below" in sentence else None


@pytest.mark.parametrize(
    "package",
    sorted(p.parent for p in SRC.glob("*/__init__.py") if p.parent.name != "cli"),
    ids=lambda p: p.name,
)
def test_may_import_says_what_the_code_imports(package: Path) -> None:
    """The "May import" line of a subpackage docstring is its real imports.

    An explicit list must equal the units the code imports; "everything in X and
    below" must cover them, and X must be one of them (the tightest such line).
    """
    import importlib

    doc = importlib.import_module(f"seapass.{package.name}").__doc__ or ""
    named, below = _may_import(doc)
    used = _used_layers(package)
    if below is None:
        assert named == used, f"the docstring says {sorted(named)}; the code imports {sorted(used)}"
    else:
        allowed = {u for u, r in RANK.items() if r <= RANK[below]}
        assert used <= allowed and below in used, (
            f"'everything in {below} and below' but the code imports {sorted(used)}"
        )


def test_import_seapass_is_light() -> None:
    code = (
        "import sys, seapass; "
        "heavy = [m for m in ('sympy', 'numpy', 'scipy', 'matplotlib', 'control', 'dask', "
        "'pyarrow') if m in sys.modules]; print(','.join(heavy))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "", f"import seapass loads {out.stdout.strip()}"


def test_the_command_line_starts_light() -> None:
    """Building the parser (``seapass --help``, every command's start) imports no heavy
    package: a command loads what it needs when it runs."""
    code = (
        "import sys; from seapass.cli import build_parser; build_parser(); "
        "heavy = [m for m in ('sympy', 'numpy', 'scipy', 'matplotlib', 'control', 'dask', "
        "'pyarrow', 'flint') if m in sys.modules]; print(','.join(heavy))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "", f"building the CLI parser loads {out.stdout.strip()}"


def test_witness_help_shows_the_human_limb_box() -> None:
    from seapass.analysis.environment_box import HUMAN_LIMB
    from seapass.cli.cmd_witness import HELP_DEFAULTS

    assert {k: list(v) for k, v in HELP_DEFAULTS.items()} == HUMAN_LIMB.to_dict()


def test_lazy_names_resolve() -> None:
    import seapass

    for name in seapass.__all__:
        assert getattr(seapass, name) is not None, name
    assert set(dir(seapass)) >= set(seapass.__all__)
    with pytest.raises(AttributeError, match="nothing"):
        _ = seapass.nothing  # type: ignore[attr-defined]


def test_every_layer_is_reachable_from_the_front_door() -> None:
    """``seapass.<unit>`` works for every subpackage and top-level module of `LAYERS`."""
    import seapass

    for group in LAYERS:
        for name in group:
            if name == "version":
                continue  # ``seapass.__version__`` is its one name
            assert getattr(seapass, name).__name__ == f"seapass.{name}", name
            assert name in dir(seapass), name
