"""The packages' layout as the developers' guide states it, read from the source (every import: at
module level, inside functions, under ``TYPE_CHECKING``):

* no import circle among the modules of ``macro``, ``micro`` and ``comparison`` (a module never
  reaches itself through the modules it imports), so that each can be read, and changed, from the
  ground up;
* ``macro`` and ``micro`` import neither each other nor ``comparison``: ``comparison`` composes them.

The same check by hand, from the repository's root: ``python tests/comparison/test_package_layout.py``
prints the circles (none) and the forbidden imports (none).
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = ("macro", "micro", "comparison")


def modules() -> dict[str, Path]:
    """Every module of the packages by its dotted name (a package by its ``__init__.py``)."""
    out = {}
    for package in PACKAGES:
        for path in (ROOT / package).rglob("*.py"):
            parts = list(path.relative_to(ROOT).with_suffix("").parts)
            out[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return out


def import_graph() -> dict[str, set[str]]:
    """Module -> the modules of the packages it imports (``from a.b import c`` names the module ``a.b.c``
    where there is one, else ``a.b``)."""
    mods = modules()

    def known(name: str) -> str | None:
        while name and name not in mods:
            name = name.rpartition(".")[0]
        return name or None

    graph: dict[str, set[str]] = {}
    for name, path in mods.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        edges: set[str] = set()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                edges |= {t for a in node.names if (t := known(a.name))}
            elif isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    up = package.split(".")[: len(package.split(".")) - node.level + 1]
                    base = ".".join(up + ([base] if base else []))
                for a in node.names:
                    target = f"{base}.{a.name}" if f"{base}.{a.name}" in mods else known(base)
                    if target:
                        edges.add(target)
        graph[name] = edges - {name}
    return graph


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan's algorithm, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []
    for root in graph:
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            v, children = work[-1]
            for w in children:
                if w not in index:
                    index[w] = low[w] = len(index)
                    stack.append(w)
                    on_stack.add(w)
                    work.append((w, iter(sorted(graph[w]))))
                    break
                if w in on_stack:
                    low[v] = min(low[v], index[w])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[v])
                if low[v] == index[v]:
                    component = []
                    while True:
                        w = stack.pop()
                        on_stack.discard(w)
                        component.append(w)
                        if w == v:
                            break
                    if len(component) > 1:
                        found.append(sorted(component))
    return found


def forbidden(graph: dict[str, set[str]]) -> list[str]:
    """Imports of ``macro`` or ``micro`` into the other, or of ``comparison`` into either."""
    never = {"macro": ("micro", "comparison"), "micro": ("macro", "comparison"), "comparison": ()}
    return sorted(f"{m} -> {t}" for m, targets in graph.items() for t in targets
                  if t.split(".")[0] in never[m.split(".")[0]])


def test_no_import_circle_in_the_packages() -> None:
    assert circles(import_graph()) == []


def test_the_circle_finder_finds_a_circle() -> None:
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}, "e": set()}
    assert circles(graph) == [["a", "b", "c"]]


def test_macro_and_micro_import_neither_each_other_nor_comparison() -> None:
    assert forbidden(import_graph()) == []


if __name__ == "__main__":
    g = import_graph()
    print(f"{len(g)} modules; circles: {circles(g)}; forbidden imports: {forbidden(g)}")


#: The most lines a library module may have (the developers' guide: split along the seam, never trim docs).
MAX_MODULE_LINES = 500


def test_every_library_module_stays_under_500_lines() -> None:
    """A module of ``macro``, ``micro`` or ``comparison`` longer than :data:`MAX_MODULE_LINES` is named with
    its count (cut it along its seam)."""
    over = [f"{path.relative_to(ROOT)}: {n} lines" for package in PACKAGES
            for path in sorted((ROOT / package).rglob("*.py"))
            if (n := len(path.read_text(encoding="utf-8").splitlines())) >= MAX_MODULE_LINES]
    assert not over, over
