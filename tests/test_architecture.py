"""The layers of docs/architecture.md, kept true: every import inside the package goes to a
lower layer or stays in its own subpackage (no climb, no sideways step between peers), and
no module grows past 450 lines."""

from __future__ import annotations

import ast
import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "facing_service"

#: Bottom to top, as docs/architecture.md draws them; peers share a rank.
LAYERS = {
    "contract": 0,
    "core": 1,
    "ros2": 2,
    "config": 3,
    "shell": 4,
    "client": 4,
    "tools": 5,
    "camera": 5,  # the camera front end: beside tools/, imported only by the commands
}
TOP = 6  # cli, __main__, testing: the package's entry points, above every subpackage


def layer_of(parts: tuple[str, ...]) -> tuple[int, str]:
    """(rank, subpackage) of a module, given as its parts under facing_service/."""
    if parts and parts[0] in LAYERS:
        return LAYERS[parts[0]], parts[0]
    return TOP, ""


def targets(here: tuple[str, ...], source: str) -> list[tuple[tuple[str, ...], str]]:
    """Every package-internal import of the module ``here``: (target parts, name)."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.ImportFrom):
            module = (node.module or "").split(".") if node.module else []
            if node.level:
                base = list(here[: len(here) - node.level])
            elif module[:1] == ["facing_service"]:
                base, module = [], module[1:]
            else:
                continue
            for alias in node.names:
                found.append((tuple(base + module), alias.name))
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.startswith("facing_service."):
                    found.append((tuple(alias.name.split(".")[1:]), ""))
    return found


def climbs(here: tuple[str, ...], source: str) -> list[str]:
    """The imports of module ``here`` that go to its own layer (another package) or up."""
    rank, package = layer_of(here)
    wrong = []
    for target, name in targets(here, source):
        if not target:  # the package root: only its version, set before it imports anything
            if name != "__version__":
                wrong.append(f"facing_service.{name}")
            continue
        their_rank, theirs = layer_of(target)
        if theirs == package:  # within one subpackage (or among the entry points)
            continue
        if their_rank >= rank:
            wrong.append(".".join(target))
    return wrong


MODULES = sorted(p for p in PACKAGE.rglob("*.py") if p.parent != PACKAGE or p.stem != "__init__")


def test_every_subpackage_has_a_layer():
    assert {p.parent.name for p in PACKAGE.glob("*/__init__.py")} == set(LAYERS)


@pytest.mark.parametrize("path", MODULES, ids=lambda p: str(p.relative_to(PACKAGE)))
def test_imports_only_go_down(path: Path):
    here = path.relative_to(PACKAGE).with_suffix("").parts
    assert climbs(here, path.read_text()) == []


@pytest.mark.parametrize(
    ("here", "source", "wrong"),
    [
        (("core", "tracker"), "from ..shell.service import FacingService", ["shell.service"]),
        (("client", "watch"), "from ..shell import outbox", ["shell"]),  # peers: sideways
        (("contract", "keys"), "from facing_service.core import tracker", ["core"]),
        (("ros2", "people"), "from .. import cli", ["facing_service.cli"]),
        (("shell", "service"), "from ..core.tracker import Tracker\nfrom .outbox import O", []),
    ],
)
def test_the_rule_catches_a_climb(here, source, wrong):
    assert climbs(here, source) == wrong


#: docs/architecture.md: one responsibility per module, none over this many lines. (A
#: cap of 400 split modules by size rather than by what they do; a cohesive 420 lines beats
#: two halves that call each other.)
MAX_MODULE_LINES = 450


#: The benchmarks keep the package's caps (modules of 604 and 606 lines, a
#: ``main`` of 136 that did an hour's work inline).
BENCHMARK_MODULES = sorted((PACKAGE.parent / "benchmarks").rglob("*.py"))


@pytest.mark.parametrize(
    "path", MODULES + BENCHMARK_MODULES, ids=lambda p: str(p.relative_to(PACKAGE.parent))
)
def test_no_module_is_over_450_lines(path: Path):
    lines = len(path.read_text().splitlines())
    assert lines <= MAX_MODULE_LINES, f"{path.relative_to(PACKAGE.parent)}: {lines} lines"


def module_graph() -> dict[tuple[str, ...], set[tuple[str, ...]]]:
    """Module -> the package modules it imports (``from pkg import name`` is the module
    ``pkg.name`` when there is one, else ``pkg`` itself, its ``__init__``)."""
    known = {p.relative_to(PACKAGE).with_suffix("").parts for p in PACKAGE.rglob("*.py")}
    graph: dict[tuple[str, ...], set[tuple[str, ...]]] = {}
    for path in PACKAGE.rglob("*.py"):
        here = path.relative_to(PACKAGE).with_suffix("").parts
        if here[-1] == "__init__":
            here = here[:-1]
        source_parts = path.relative_to(PACKAGE).with_suffix("").parts
        edges = set()
        for target, name in targets(source_parts, path.read_text()):
            if (*target, name) in known:
                edges.add((*target, name))
            elif (*target,) in known or (*target, "__init__") in known:
                edges.add(target)
        graph[here] = edges - {here}
    return graph


def circles(graph: dict[tuple[str, ...], set[tuple[str, ...]]]) -> list[list[str]]:
    """Every import circle (one path around each strongly connected set of modules)."""
    found, done, path = [], set(), []

    def visit(node: tuple[str, ...]) -> None:
        if node in path:
            found.append([".".join(n) for n in path[path.index(node) :]])
            return
        if node in done:
            return
        path.append(node)
        for target in sorted(graph.get(node, ())):
            visit(target)
        path.pop()
        done.add(node)

    for node in sorted(graph):
        visit(node)
    return found


def test_no_import_circles():
    """A defect found: config.session and config.settings imported each other."""
    assert circles(module_graph()) == []


def test_the_circle_finder_finds_one():
    assert circles({("a",): {("b",)}, ("b",): {("a",)}}) == [["a", "b"]]


def test_importing_the_client_loads_no_ros2_and_no_tf():
    """An application that only reads results pays neither the ROS 2 adapter (rosbags'
    type store) nor the TF buffer: ``from facing_service import FacingClient`` loads the
    contract, the settings and the client alone."""
    code = (
        "import json, sys\nimport facing_service\nfrom facing_service import FacingClient\n"
        "print(json.dumps(sorted(sys.modules)))"
    )
    loaded = json.loads(subprocess.run([sys.executable, "-c", code], capture_output=True,
                                       text=True, check=True).stdout)  # fmt: skip
    ours = [m for m in loaded if m.startswith("facing_service.")]
    assert [m for m in ours if m.split(".")[1] in ("ros2", "core", "shell", "tools")] == []
    assert [m for m in loaded if m.split(".")[0] in ("rosbags", "numpy")] == []


#: The layers whose every module has a test file of its own beside its twin.
MIRRORED = ("contract", "core", "ros2", "config", "shell")


@pytest.mark.parametrize("layer", MIRRORED)
def test_every_module_has_its_test_file(layer):
    """``facing_service/<layer>/<module>.py`` is tested in
    ``tests/<layer>/test_<module>.py`` (or ``test_<module>_<behaviour>.py``)."""
    tests = PACKAGE.parent / "tests" / layer
    missing = [
        module.stem
        for module in sorted((PACKAGE / layer).glob("*.py"))
        if module.stem != "__init__"
        and not (tests / f"test_{module.stem}.py").exists()
        and not list(tests.glob(f"test_{module.stem}_*.py"))
    ]
    assert not missing, f"no tests/{layer}/test_<module>.py for {missing}"


ARCHITECTURE = (PACKAGE.parent / "docs" / "architecture.md").read_text()
_BLOCKS = re.findall(r"```\n(.*?)```", ARCHITECTURE, re.S)


def defined_names(path: Path) -> set[str]:
    tree = ast.parse(path.read_text())
    return {
        node.name
        for node in ast.walk(tree)
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef)
    }


def test_the_layer_diagram_names_every_module():
    """A defect found: the diagram of docs/architecture.md named 4 fewer modules of
    core/ than there are (and core/__init__ named 4 of 13): a reader's map with holes."""
    (diagram,) = [b for b in _BLOCKS if "contract/" in b and "imports nothing" in b]
    named = set(re.findall(r"[a-z_0-9]+", diagram))
    missing = [
        f"{layer}/{path.stem}"
        for layer in LAYERS
        for path in sorted((PACKAGE / layer).rglob("*.py"))  # subpackages' modules too
        if path.stem != "__init__"
        and path.stem not in named
        and not (path.parent.name != layer and f"{path.parent.name}/" in diagram)
    ]
    assert not missing, f"docs/architecture.md's layer diagram does not name {missing}"


def test_the_core_says_what_each_of_its_modules_is():
    doc = ast.get_docstring(ast.parse((PACKAGE / "core" / "__init__.py").read_text())) or ""
    missing = [
        p.stem for p in sorted((PACKAGE / "core").glob("*.py"))
        if p.stem != "__init__" and f"``{p.stem}``" not in doc
    ]  # fmt: skip
    assert not missing, f"core/__init__.py does not say what {missing} are"


_STEP = re.compile(r"^\s*(\w+)/(\w+)\s{2,}(.*)$")
_NAME = re.compile(r"[A-Za-z_]\w*(?:\.[A-Za-z_]\w*)*")


def steps_named(block: str) -> list[tuple[str, str, str]]:
    """(layer, module, name) of each step a pipeline names: a line ``layer/module  a -> b``
    whose parts are identifiers (``Class.method``), each part up to its ``:`` or ``(``;
    parts naming another module (``x/y``) and lines of prose are not steps."""
    found = []
    for line in block.splitlines():
        if not (step := _STEP.match(line)):
            continue
        layer, module, rest = step.groups()
        for part in rest.split("->"):
            head = re.split(r"[:(]", part, maxsplit=1)[0].strip()
            if "/" in head or not _NAME.fullmatch(head):
                if part is rest.split("->")[0]:
                    break  # prose, not a chain of steps
                continue
            found.append((layer, module, head))
    return found


def test_the_pipelines_name_functions_that_exist():
    """The ways through the folders name each step as module and function: each function
    is defined in the module named (``hand_over`` stayed there after its rename to
    ``to_outbox``)."""
    wrong = []
    for layer, module, name in (s for block in _BLOCKS for s in steps_named(block)):
        path = PACKAGE / layer / f"{module}.py"
        if not path.exists() or name.split(".")[-1] not in defined_names(path):
            wrong.append(f"{layer}/{module}: {name}")
    assert not wrong, wrong
    assert len([s for block in _BLOCKS for s in steps_named(block)]) >= 10  # it reads them


#: The composition root and what runs it: the only modules of the shell that read the
#: settings; config/ makes the core's parameters from them, the commands (cli,
#: tools, camera) and the client read their own flags.
SETTINGS_READERS = {("shell", "compose"), ("shell", "service"), ("shell", "run")}


def test_below_the_composition_root_nothing_reads_the_settings():
    readers = []
    for path in MODULES:
        here = path.relative_to(PACKAGE).with_suffix("").parts
        if here[0] not in ("shell", "core", "ros2", "contract") or here in SETTINGS_READERS:
            continue
        if any(target[-1:] == ("settings",) or name == "Settings"
               for target, name in targets(here, path.read_text())):  # fmt: skip
            readers.append("/".join(here))
    assert not readers, f"read the settings below the composition root: {readers}"


def test_no_constructor_in_the_shell_takes_more_than_five_things():
    """A collaborator given what it uses takes few things (Worker took nine, Decisions
    eight, before the composition root)."""
    wide = []
    for path in sorted((PACKAGE / "shell").glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.FunctionDef) and node.name == "__init__":
                taken = len(node.args.args) - 1 + len(node.args.kwonlyargs)
                if taken > 5:
                    wide.append(f"{path.stem}: {taken}")
    assert not wide, wide


#: Argument tables: a flat list of add_argument calls reads best whole.
ARGUMENT_TABLES = {("arguments", "build_parser")}
MAX_FUNCTION_LINES = 60


def test_no_function_is_over_60_lines():
    """A function a reader holds in their head at once."""
    long = []
    for path in MODULES + BENCHMARK_MODULES:
        module = path.with_suffix("").name
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                lines = node.end_lineno - node.lineno + 1  # type: ignore[operator]
                if lines > MAX_FUNCTION_LINES and (module, node.name) not in ARGUMENT_TABLES:
                    long.append(f"{path.relative_to(PACKAGE.parent)}: {node.name} ({lines})")
    assert not long, long


BENCHMARKS = PACKAGE.parent / "benchmarks"


def _benchmark_module(path: Path) -> str:
    """``benchmarks/groups/join.py`` -> ``groups.join``; a package's ``__init__`` -> its
    folder's name."""
    parts = path.relative_to(BENCHMARKS).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def benchmark_graph() -> dict[str, set[str]]:
    """benchmarks' module (``perf.churn``) -> the benchmarks modules it imports, wherever
    the import stands (an import inside a function dodges a circle at import time, not in
    the design), relative imports resolved from the module's own folder."""
    paths = {_benchmark_module(p): p for p in BENCHMARKS.rglob("*.py")}
    graph: dict[str, set[str]] = {}
    for here, path in paths.items():
        folder = here.split(".")[:-1] if path.stem != "__init__" else here.split(".")
        found = set()
        for node in ast.walk(ast.parse(path.read_text())):
            if not isinstance(node, ast.ImportFrom):
                continue
            if node.level:
                base = ".".join(
                    [*folder[: len(folder) - node.level + 1], *filter(None, [node.module])]
                )
            elif (node.module or "").startswith("benchmarks"):
                base = (node.module or "").removeprefix("benchmarks").strip(".")
            else:
                continue
            for alias in node.names:  # ``from .perf import churn`` names a module
                joined = f"{base}.{alias.name}".strip(".")
                found.add(joined if joined in paths else base)
        graph[here] = {m for m in found if m in paths} - {here}
    return graph


def test_benchmarks_have_no_import_circle():
    """A defect found: crossval <-> recordings and groups <-> group_scenes were circles dodged by
    imports inside functions; what both needed has a module of its own now."""
    graph = benchmark_graph()
    circles = []
    for start in graph:
        stack, seen = [(start, [start])], set()
        while stack:
            here, path = stack.pop()
            for there in graph[here]:
                if there == start:
                    circles.append(" -> ".join([*path, start]))
                elif there not in seen:
                    seen.add(there)
                    stack.append((there, [*path, there]))
    assert not circles, circles


TESTS = PACKAGE.parent / "tests"
#: The tests of benchmarks/ itself, and of the pages it generates: they import it.
OF_BENCHMARKS = re.compile(r"test_benchmarks(_\w+)?\.py|test_docs\.py")


def test_the_package_tests_import_nothing_from_benchmarks():
    """A defect found: six of the package's tests imported benchmarks (a bag reader, the hot
    path's harness, a memory reading, GCFF's parameters): a change to a measurement
    script could break or bend a unit test. They use tests/support or build their own."""
    importing = []
    for path in sorted(TESTS.rglob("*.py")):
        if OF_BENCHMARKS.fullmatch(path.name):
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            names = (
                [a.name for a in node.names] if isinstance(node, ast.Import)
                else [node.module or ""] if isinstance(node, ast.ImportFrom) else []
            )  # fmt: skip
            if any(n == "benchmarks" or n.startswith("benchmarks.") for n in names):
                importing.append(str(path.relative_to(TESTS)))
    assert not importing, importing


AREAS = ("perf", "engagement", "groups")
SHARED_BY_AREAS = {"paths", "sections", "results_file"}


def test_each_benchmark_area_imports_only_itself_and_what_all_share():
    """Benchmarks/ measures three unrelated things; each lives in its folder
    (perf/, engagement/, groups/) and reaches no other (only ``paths``, ``sections`` and
    ``results_file``, shared, and the top ``pages``, which gathers every page, reach across)."""
    across = {
        here: sorted(m for m in imported if m.split(".")[0] != area and m not in SHARED_BY_AREAS)
        for here, imported in benchmark_graph().items()
        if (area := here.split(".")[0]) in AREAS
    }
    assert not {k: v for k, v in across.items() if v}


def test_every_results_file_is_written_with_its_provenance():
    """A defect found: provenance (version, machine, date, command, parameters) was in two
    results files of seven. Every benchmark writes its results through
    ``benchmarks.results_file``, which puts it first: no other module writes JSON."""
    writers = []
    for path in sorted(BENCHMARKS.rglob("*.py")):
        if path.name == "results_file.py":
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            writes = isinstance(node, ast.Call) and getattr(node.func, "attr", "") == "write_text"
            if writes and any(
                isinstance(n, ast.Call) and getattr(n.func, "attr", "") == "dumps"
                for n in ast.walk(node)
            ):
                writers.append(f"{path.relative_to(BENCHMARKS)}:{node.lineno}")
    assert not writers, writers
