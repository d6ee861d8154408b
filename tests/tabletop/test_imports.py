"""The project's modules import each other without a cycle, counting imports made inside
functions (a cycle hidden in a function works until someone moves the import to the top)."""

import ast
import functools
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = ("tabletop", "tracking", "calibration", "behaviors")


def modules() -> dict[str, Path]:
    found = {}
    for package in PACKAGES:
        for path in (ROOT / package).rglob("*.py"):
            name = ".".join(path.relative_to(ROOT).with_suffix("").parts)
            found[name.removesuffix(".__init__")] = path
    return found


def statements(nodes: list[ast.stmt]):
    """Every statement of ``nodes`` and of the blocks within them (functions, classes, ifs,
    loops, withs, trys, matches): an import is always a statement, so the expressions, most of
    a module's nodes, are not walked (0.8 of ast.walk's CPU s over the project)."""
    for node in nodes:
        yield node
        for block in ("body", "orelse", "finalbody", "handlers", "cases"):
            yield from statements(getattr(node, block, None) or ())


def imported(path: Path, known: dict[str, Path]) -> set[str]:
    """The project modules ``path`` imports anywhere in its text."""
    out = set()
    for node in statements(ast.parse(path.read_text(encoding="utf-8")).body):
        if isinstance(node, ast.Import):
            out.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            out.add(node.module)
            out.update(f"{node.module}.{a.name}" for a in node.names)
    return {m for m in out if m in known}


def cycle_through(start: str, graph: dict[str, set[str]]) -> list[str] | None:
    """A path start -> ... -> start, if there is one (depth-first)."""
    stack, seen = [(start, [start])], set()
    while stack:
        node, path = stack.pop()
        for nxt in sorted(graph[node]):
            if nxt == start:
                return path + [start]
            if nxt not in seen:
                seen.add(nxt)
                stack.append((nxt, path + [nxt]))
    return None


@functools.cache
def import_graph() -> dict[str, set[str]]:
    """Each project module's project imports, itself left out: both tests read it (parsing the
    project's ~290 files is most of their CPU, once per module here)."""
    known = modules()
    return {m: imported(p, known) - {m} for m, p in known.items()}


def test_no_import_cycles():
    graph = import_graph()
    cycles = [c for m in sorted(graph) if (c := cycle_through(m, graph))]
    assert not cycles, " | ".join(" -> ".join(c) for c in cycles[:5])


def layer_breaks() -> list[str]:
    """DESIGN.md's layers: ``tabletop.frames`` and ``tabletop.files`` (with its parts
    ``tabletop.file_io`` and ``tabletop.names``) import nothing of the project but each
    other (the files' errors are the vocabulary's ``InputError``, kept numpy-free in
    ``tabletop.errors``); ``tracking``,
    ``calibration`` and ``behaviors`` import those and nothing of each other but ``tracking``
    using ``calibration``; only ``tabletop`` wires everything."""
    shared = {"tabletop.frames", "tabletop.errors", "tabletop.files", "tabletop.file_io",
              "tabletop.names"}
    allowed = {"tracking": {"tracking", "calibration"}, "calibration": {"calibration"},
               "behaviors": {"behaviors"}}
    breaks = []
    for name, imports in sorted(import_graph().items()):
        targets = set(imports)
        targets = {m for m in targets if not any(o.startswith(m + ".") for o in targets)}
        if name in shared:
            breaks += [f"{name} -> {m}" for m in sorted(targets - shared)]
        elif (package := name.split(".")[0]) in allowed:
            breaks += [f"{name} -> {m}" for m in sorted(targets)
                       if m not in shared and m.split(".")[0] not in allowed[package]]
    return breaks


def test_the_layers_of_the_design():
    breaks = layer_breaks()
    assert not breaks, " | ".join(breaks)
