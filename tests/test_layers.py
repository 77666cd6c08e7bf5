"""Layers look only down (issue 25): every import in every .py file of the repository, read with
ast (imports inside functions included, and importlib.import_module / __import__ of a literal
name), points at its own package or at a lower layer.

The order, lowest first (the README's layout table gives the same):

    model      the library: the hardware twin (model/hw), the scene library (format, front end,
               meshes, passes, truth), the float reference, and model.cli, the one-line-error
               parser, staged outputs and progress bar that every command shares
    hdlbuild   builds and runs an RTL top under Icarus or Verilator
    sim, synth, formal
               full-frame RTL simulation; Yosys and the ECP5 flow; the formal proofs (side by
               side: none imports another)
    app        the command layer: render, animation (its --rtl runs sim), precision, quality, needs
    verify     beside app: make mutants (verify.mutants runs tb/ and sim.frame as commands, importing neither)
    explore    the design-space sweep, fit and filters, built on all of the above (filters runs
               app.render and app.animation, fit and measure use app.needs and app.quality)

tb/ and tests/ (and the root conftest.py) stand above every layer and are imported by nothing
but themselves (tb's testbenches share tb/pipe.py). No module imports another module's private
name (`from X import _name`). Every package at the top of the repository must be placed here.
"""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

LAYERS = (("model",), ("hdlbuild",), ("sim", "synth", "formal"), ("app", "verify"), ("explore",))
TOP = ("tb", "tests")  # above every layer; imported only by themselves
SKIP_DIRS = {"build", "out", "node_modules", "__pycache__"}


def level(pkg: str) -> int | None:
    for i, names in enumerate(LAYERS):
        if pkg in names:
            return i
    return None


def python_files(root: Path):
    for f in sorted(root.rglob("*.py")):
        rel = f.relative_to(root)
        if any(p.startswith(".") or p in SKIP_DIRS for p in rel.parts[:-1]):
            continue
        yield rel


def imports(path: Path):
    """(line, imported module, names imported from it) of every import in the file, relative
    imports resolved against the file's package."""
    tree = ast.parse(path.read_text(), filename=str(path))
    pkg_parts = list(path.parts[:-1])  # the file's package (an __init__.py's own)
    for n in ast.walk(tree):
        if isinstance(n, ast.Import):
            for a in n.names:
                yield n.lineno, a.name, ()
        elif isinstance(n, ast.ImportFrom):
            if n.level:
                base = pkg_parts[:len(pkg_parts) - (n.level - 1)] if n.level > 1 else pkg_parts
                mod = ".".join(base + ([n.module] if n.module else []))
            else:
                mod = n.module or ""
            yield n.lineno, mod, tuple(a.name for a in n.names)
        elif (isinstance(n, ast.Call) and n.args and isinstance(n.args[0], ast.Constant)
              and isinstance(n.args[0].value, str)
              and ((isinstance(n.func, ast.Attribute) and n.func.attr == "import_module")
                   or (isinstance(n.func, ast.Name) and n.func.id in ("__import__", "import_module")))):
            yield n.lineno, n.args[0].value, ()


def violations(root: Path) -> list[str]:
    """Every import under root that points up a layer, at a peer, at tb/ or tests/, or at a
    private name of another module; and every top-level package not placed in LAYERS or TOP."""
    root = Path(root)
    known = {p for names in LAYERS for p in names} | set(TOP)
    out = [f"{d.name}/: a package not placed in the layer order (tests/test_layers.py LAYERS)"
           for d in sorted(root.iterdir())
           if d.is_dir() and (d / "__init__.py").is_file() and d.name not in known and not d.name.startswith(".")]
    for rel in python_files(root):
        src = rel.parts[0] if len(rel.parts) > 1 else "tests"  # a root file (conftest.py): a test
        lv_src = level(src)
        this_mod = ".".join(rel.with_suffix("").parts)
        for line, mod, names in imports(root / rel):
            dst = mod.split(".")[0]
            if dst not in known:
                continue  # the standard library or a third-party package
            where = f"{rel}:{line}: {src} imports {mod}"
            if dst != src:
                lv_dst = level(dst)
                if dst in TOP:
                    out.append(f"{where} ({dst}/ is imported by nothing but itself)")
                elif lv_src is not None and lv_dst >= lv_src:
                    out.append(f"{where} ({dst} is {'beside' if lv_dst == lv_src else 'above'} {src} "
                               "in the layer order)")
            if mod != this_mod:
                out += [f"{where} ({n}: a private name of another module)" for n in names
                        if n.startswith("_") and not n.startswith("__")]
    return out


def test_layers_look_only_down():
    bad = violations(ROOT)
    assert not bad, "imports against the layer order " + " < ".join("|".join(x) for x in LAYERS) + ":\n" + "\n".join(bad)


@pytest.mark.parametrize("path,text,found", [
    ("model/scene/x.py", "def f():\n    from sim.frame_rtl import run_passes_rtl\n", "sim is above model"),
    ("model/x.py", "import hdlbuild\n", "hdlbuild is above model"),
    ("model/x.py", "import importlib\nimportlib.import_module('app.render')\n", "app is above model"),
    ("sim/x.py", "from synth import run\n", "synth is beside sim"),
    ("app/x.py", "from explore.space import plan\n", "explore is above app"),
    ("explore/x.py", "from tb import pipe\n", "tb/ is imported by nothing but itself"),
    ("app/x.py", "from model.scene.truth import _tile\n", "_tile: a private name"),
    ("model/scene/x.py", "from . import truth\nfrom ..hw import golden\n", None),
    ("tests/test_x.py", "from explore.space import plan\nfrom model.scene import truth\n", None),
    ("tests/test_x.py", "from tb import pipe\n", "tb/ is imported by nothing but itself"),
    ("newpkg/x.py", "", "newpkg/: a package not placed"),
])
def test_a_planted_violation_is_found(tmp_path, path, text, found):
    """The checker itself: each planted import is reported (and a legal relative one is not)."""
    for pkg in ("model", "model/scene", "model/hw", "sim", "synth", "app", "explore", "tb", "tests", "newpkg"):
        (tmp_path / pkg).mkdir(parents=True, exist_ok=True)
        (tmp_path / pkg / "__init__.py").write_text("")
    if path.startswith("newpkg/"):
        (tmp_path / "newpkg" / "__init__.py").write_text("")
    else:
        (tmp_path / "newpkg" / "__init__.py").unlink()
    (tmp_path / path).write_text(text)
    bad = violations(tmp_path)
    if found is None:
        assert bad == []
    else:
        assert len(bad) == 1 and found in bad[0], bad


def _calls_hdlbuild_run(path: Path) -> list[int]:
    """Lines of `path` that call hdlbuild.run (hdlbuild.run(...), or run imported from hdlbuild)."""
    tree = ast.parse(path.read_text())
    runs = {a.asname or a.name for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) and n.module == "hdlbuild"
            for a in n.names if a.name == "run"}
    return [n.lineno for n in ast.walk(tree) if isinstance(n, ast.Call) and (
        (isinstance(n.func, ast.Attribute) and n.func.attr == "run" and isinstance(n.func.value, ast.Name)
         and n.func.value.id == "hdlbuild") or (isinstance(n.func, ast.Name) and n.func.id in runs))]


def test_block_testbenches_launch_through_run_block():
    """One testbench idiom: every block testbench (tb/<block>/test_*.py) is built and run by
    tb/pipe.py's run_block (or block_test, its pytest entry), never by hdlbuild.run itself."""
    tbs = sorted((ROOT / "tb").glob("*/test_*.py"))
    assert tbs
    bad = [f"{f.relative_to(ROOT)}:{line}" for f in tbs for line in _calls_hdlbuild_run(f)]
    assert not bad, "hdlbuild.run called by hand (use tb.pipe.run_block): " + ", ".join(bad)
    assert _calls_hdlbuild_run(ROOT / "tb" / "pipe.py"), "tb/pipe.py's run_block no longer launches through hdlbuild.run"
