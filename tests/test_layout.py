"""The tests mirror the package (issue 21, item 9): ``tests/<subpackage>/test_<module>.py``.

* a flat ``tests/test_*.py`` is only a test of a top-level module of seapass
  (``test_outcome.py`` for ``seapass/outcome.py``) or a house rule about the whole
  package (`PACKAGE_WIDE`);
* every directory under ``tests/`` (other than `NOT_TESTS`) is named after a real
  subpackage of seapass and is a package (an empty ``__init__.py``), so that test
  files with the same name in two directories do not collide;
* ``tests/`` itself is not a package (pytest puts it on ``sys.path``, which is how the
  tests import ``helpers``, ``hostile``, ``cpu_budget`` and ``long_jobs``).
"""

from __future__ import annotations

from pathlib import Path

TESTS = Path(__file__).resolve().parent
SRC = TESTS.parent / "src" / "seapass"

#: flat test files about the package as a whole, not one module
PACKAGE_WIDE = {
    "test_architecture.py": "imports point down, module sizes, names (docs/architecture.md)",
    "test_layout.py": "this file",
    "test_results.py": "every result of every subpackage is frozen, keyword-only, tuples",
}
#: directories under tests/ that hold no tests
NOT_TESTS = {"data", "__pycache__"}


def layout_problems(tests: Path, src: Path) -> list[str]:
    """Every way ``tests`` fails to mirror the package at ``src``, one line each."""
    problems = []
    modules = {p.stem for p in src.glob("*.py") if p.stem != "__init__"}
    subpackages = {p.parent.name for p in src.glob("*/__init__.py")}
    for f in sorted(tests.glob("test_*.py")):
        if f.name not in PACKAGE_WIDE and f.stem.removeprefix("test_") not in modules:
            problems.append(
                f"tests/{f.name}: not a top-level module's test; move it to "
                "tests/<subpackage>/test_<module>.py (or list it in PACKAGE_WIDE with the reason)"
            )
    for d in sorted(p for p in tests.iterdir() if p.is_dir() and not p.name.startswith(".")):
        if d.name in NOT_TESTS:
            continue
        if d.name not in subpackages:
            problems.append(f"tests/{d.name}/: no subpackage seapass.{d.name}")
        if not (d / "__init__.py").is_file():
            problems.append(f"tests/{d.name}/: no __init__.py (test file names would collide)")
    if (tests / "__init__.py").exists():
        problems.append("tests/__init__.py: tests/ itself must not be a package")
    return problems


def test_the_tests_mirror_the_package() -> None:
    problems = layout_problems(TESTS, SRC)
    assert not problems, "\n".join(problems)


def test_package_wide_files_exist() -> None:
    stale = sorted(name for name in PACKAGE_WIDE if not (TESTS / name).is_file())
    assert not stale, f"PACKAGE_WIDE lists files that are gone: {stale}"


def test_the_layout_check_sees_what_it_forbids(tmp_path: Path) -> None:
    src = tmp_path / "src"
    (src / "model").mkdir(parents=True)
    (src / "model" / "__init__.py").touch()
    (src / "outcome.py").touch()
    tests = tmp_path / "tests"
    for name in ("model", "nowhere", "data"):
        (tests / name).mkdir(parents=True)
    (tests / "model" / "__init__.py").touch()
    for name in ("test_outcome.py", "test_architecture.py", "test_exactpoly.py"):
        (tests / name).touch()
    (tests / "__init__.py").touch()
    problems = layout_problems(tests, src)
    assert len(problems) == 4, problems
    assert problems[0].startswith("tests/test_exactpoly.py: not a top-level module's test")
    assert problems[1] == "tests/nowhere/: no subpackage seapass.nowhere"
    assert problems[2].startswith("tests/nowhere/: no __init__.py")
    assert problems[3].startswith("tests/__init__.py")
