"""The package's layout as a contract: data flows one way through layers, no import circle, no arrow back
up, and no plug-in imports a sibling plug-in.

Every import of every module of ``src/bounce`` is read with ``ast`` (function-level imports included, as
they run too), resolved to the module it loads, and checked against :data:`LAYERS`: a module may import
its own layer or one below, never one above.  A plug-in folder (claim groups, sweeps, studies, methods)
may import its own ``base`` and private helpers (``_name``), not another plug-in: what two plug-ins
share lives one layer down (``bounce.analysis``).
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "src" / "bounce"

#: layer of each top-level module or folder of bounce, from the bottom (the flow: model -> solvers -> front
#: -> shared analysis -> methods and figure helpers -> wings -> pipeline -> command line)
LAYERS = {
    "errors": 0, "kinds": 0, "paths": 0, "_registry": 0, "_jit_cache": 0, "_version": 0, "_interrupted": 0,
    "springs": 1, "model": 1,
    "trajectory": 2,
    "exact": 3, "series": 3,
    "simulate": 4, "sampling": 4,
    "io": 5, "stream": 5, "scenes": 5, "gas": 5,
    "analysis": 6,
    "methods": 7, "figures": 7,
    "studies": 8, "sweeps": 8, "checks": 8,
    "pipeline": 9,
    "claims_cli": 10, "cli": 10, "gas_cli": 10, "__main__": 10, "__init__": 10,
}
PLUGIN_FOLDERS = ("checks", "sweeps", "studies", "methods")


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _is_package(name: str) -> bool:
    return (PACKAGE.parent.joinpath(*name.split(".")) / "__init__.py").exists()


def _imports(path: Path) -> set[str]:
    """The bounce modules ``path`` imports (``from pkg import mod`` resolved to the module when it is one)."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found |= {a.name for a in node.names if a.name.split(".")[0] == "bounce"}
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if target.split(".")[0] != "bounce":
                continue
            for alias in node.names:
                sub = f"{target}.{alias.name}"
                is_module = _is_package(sub) or PACKAGE.parent.joinpath(*sub.split(".")).with_suffix(".py").exists()
                found.add(sub if is_module else target)
    return found - {name}


GRAPH = {_module_name(p): _imports(p) for p in sorted(PACKAGE.rglob("*.py"))}


def _layer(module: str) -> int:
    parts = module.split(".")
    return LAYERS["__init__"] if len(parts) == 1 else LAYERS[parts[1]]


def test_every_module_has_a_layer():
    unplaced = sorted({m.split(".")[1] for m in GRAPH if "." in m} - set(LAYERS))
    assert not unplaced, f"modules or folders of bounce without a layer in LAYERS: {unplaced}"


@pytest.mark.parametrize("module", sorted(GRAPH))
def test_no_arrow_back_up(module):
    up = sorted(t for t in GRAPH[module] if _layer(t) > _layer(module))
    assert not up, f"{module} (layer {_layer(module)}) imports from above: {[(t, _layer(t)) for t in up]}"


def test_no_import_circle():
    """Depth-first search for a cycle among modules (a package's __init__ counts as the package)."""
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(m: str) -> list[str] | None:
        state[m] = 1
        stack.append(m)
        for t in sorted(GRAPH.get(m, ())):
            if state.get(t) == 1:
                return stack[stack.index(t):] + [t]
            if t not in state and (cycle := visit(t)):
                return cycle
        state[m] = 2
        stack.pop()
        return None

    for m in sorted(GRAPH):
        if m not in state:
            cycle = visit(m)
            assert cycle is None, f"import circle: {' -> '.join(cycle)}"


@pytest.mark.parametrize("folder", PLUGIN_FOLDERS)
def test_no_plugin_imports_a_sibling(folder):
    prefix = f"bounce.{folder}."
    bad = []
    for module, targets in GRAPH.items():
        if not module.startswith(prefix):
            continue
        for t in targets:
            leaf = t[len(prefix):] if t.startswith(prefix) else None
            if leaf and leaf != "base" and not leaf.startswith("_") and t != module:
                bad.append((module, t))
    assert not bad, f"plug-ins of {folder}/ importing siblings: {bad}"


def test_the_checker_sees_an_arrow_back_up(tmp_path):
    """The reader itself can fail: a solver importing the pipeline is found (a falsifier of the test above)."""
    fake = PACKAGE / "exact" / "events.py"
    tree_imports = _imports(fake)
    assert "bounce.trajectory" in tree_imports and "bounce.kinds" in tree_imports
    assert _layer("bounce.pipeline.tasks") > _layer("bounce.exact.events")


@pytest.mark.parametrize("folder, single, family", [
    ("checks", "CHECK", "CHECKS"), ("sweeps", "SWEEP", "SWEEPS"), ("studies", "STUDY", "STUDIES"),
    ("methods", "METHOD", "METHODS"),
])
def test_every_plugin_module_is_registered(folder, single, family):
    """A plug-in is one file plus its registry line: every module of the folder (but ``base`` and private
    helpers) defines its entry (``single``, or a tuple ``family``), and the discovered registry holds every
    such entry (a misspelt registry name dropped four studies once: discovery looked for ``STUDYS``)."""
    import importlib

    package = importlib.import_module(f"bounce.{folder}")
    registered = list(package.registry().values())
    for path in sorted((PACKAGE / folder).glob("*.py")):
        if path.stem in ("__init__", "base") or path.stem.startswith("_"):
            continue
        module = importlib.import_module(f"bounce.{folder}.{path.stem}")
        entries = [e for e in (getattr(module, single, None), *getattr(module, family, ())) if e is not None]
        assert entries, f"bounce.{folder}.{path.stem} defines neither {single} nor {family}"
        missing = [e.name for e in entries if not any(e is r for r in registered)]
        assert not missing, f"bounce.{folder}.{path.stem}: {missing} not in the discovered registry"


def _imports_numba(path: Path) -> bool:
    return any(isinstance(n, ast.Import) and any(a.name.split(".")[0] == "numba" for a in n.names)
               or isinstance(n, ast.ImportFrom) and (n.module or "").split(".")[0] == "numba" and not n.level
               for n in ast.walk(ast.parse(path.read_text())))


def test_downstream_modules_define_no_kernel():
    """The numba cache is keyed by the modules kernels may read (bounce._jit_cache.kernel_sources); the parts left out
    (DOWNSTREAM: claims, figures, pipeline glue, command lines) must import no numba (define no kernel), and no module
    with kernels may import them at module level (a kernel would read a constant whose edit does not refresh the
    cache; a figure's import inside its plot function reaches no kernel)."""
    from bounce._jit_cache import DOWNSTREAM, kernel_sources

    package = Path(__file__).resolve().parents[1] / "src" / "bounce"
    kept = kernel_sources(package)
    left_out = [p for p in package.rglob("*.py") if p not in kept]
    assert left_out and all(p.relative_to(package).parts[0] in DOWNSTREAM for p in left_out)
    assert not [p for p in left_out if _imports_numba(p)], "a module left out of the cache key defines kernels"
    downstream = {d.removesuffix(".py") for d in DOWNSTREAM}
    for path in (p for p in kept if _imports_numba(p)):
        for node in ast.parse(path.read_text()).body:
            if isinstance(node, ast.ImportFrom) and node.level and node.module:
                assert node.module.split(".")[0] not in downstream, f"{path}, a module with kernels, imports {node.module}"


def test_a_job_finds_its_plugin_without_importing_the_others():
    """checks.get / sweeps.get / studies.get return the registry's object, importing only the plugin's own module
    when it is named for the plugin (a study of a family module falls back to discovery)."""
    import subprocess
    import sys

    from bounce.checks import get as get_check, registry as checks
    from bounce.studies import get as get_study, registry as studies
    from bounce.sweeps import get as get_sweep, registry as sweeps

    for get, registry in ((get_check, checks), (get_sweep, sweeps), (get_study, studies)):
        for name, obj in registry().items():
            assert get(name) == obj, name
        with pytest.raises(KeyError):
            get("no-such-plugin")
    code = ("import sys; from bounce.checks import get; get('rigid-collapse'); "
            "print(sorted(m for m in sys.modules if m.startswith('bounce.checks.')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert "bounce.checks.rigid_collapse" in out and "bounce.checks.errata" not in out, out
