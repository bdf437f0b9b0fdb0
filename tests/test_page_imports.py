"""The designer page's ES modules (marblevideo/design/web) import one another
without a cycle: their static imports (``import ... from "./x.js"``, ``export
... from``, ``import "./x.js"``) read from the sources, as a graph that
graphlib must order; every module is reached from main.js, and the store and
the plain helpers import nothing of the page. The checker itself is shown to
find a cycle, and to read every import form, in small synthetic pages."""

from __future__ import annotations

import re
from graphlib import CycleError, TopologicalSorter
from pathlib import Path

import pytest
from helpers import ROOT

pytestmark = pytest.mark.tier("fast")

WEB = ROOT / "marblevideo" / "design" / "web"
#: A static import or re-export of a relative module (its names may span lines).
IMPORT = re.compile(
    r"""^\s*(?:import|export)\s+(?:[\w$*{},\s]+?\s+from\s+)?["'](\.{1,2}/[^"']+)["']""", re.M
)
#: Modules at the bottom: every other module may use them, they use none.
LEAVES = {"store.js", "values.js", "dom.js", "api.js", "range.js"}


def imports_of(folder: Path) -> dict[str, set[str]]:
    """Each ``*.js`` module of ``folder`` and the modules of ``folder`` it imports."""
    graph = {}
    for path in sorted(folder.glob("*.js")):
        targets = set()
        for spec in IMPORT.findall(path.read_text(encoding="utf-8")):
            target = (folder / spec).resolve()
            assert target.parent == folder.resolve() and target.is_file(), (path.name, spec)
            targets.add(target.name)
        graph[path.name] = targets
    return graph


def cycle_in(graph: dict[str, set[str]]) -> list[str] | None:
    """A cycle of ``graph`` (its modules, the first repeated last), or None."""
    try:
        tuple(TopologicalSorter(graph).static_order())
    except CycleError as e:
        return list(e.args[1])
    return None


def reached(graph: dict[str, set[str]], start: str) -> set[str]:
    seen, todo = set(), [start]
    while todo:
        name = todo.pop()
        if name not in seen:
            seen.add(name)
            todo.extend(graph[name])
    return seen


def test_the_pages_modules_import_one_another_without_a_cycle():
    graph = imports_of(WEB)
    assert len(graph) > 15 and "main.js" in graph
    assert cycle_in(graph) is None
    assert reached(graph, "main.js") == set(graph)  # no module left out
    for leaf in LEAVES:
        assert graph[leaf] == set(), leaf


def test_the_checker_finds_a_cycle(tmp_path):
    (tmp_path / "a.js").write_text('import { b } from "./b.js";\nimport * as d from "./d.js";\n')
    (tmp_path / "b.js").write_text('import {\n  c,\n  cc,\n} from "./c.js";\n')
    (tmp_path / "c.js").write_text('export { a } from "./a.js";\n')
    (tmp_path / "d.js").write_text("export const d = 1;\n")
    graph = imports_of(tmp_path)
    assert graph == {"a.js": {"b.js", "d.js"}, "b.js": {"c.js"}, "c.js": {"a.js"}, "d.js": set()}
    cycle = cycle_in(graph)
    assert cycle is not None and cycle[0] == cycle[-1] and set(cycle) == {"a.js", "b.js", "c.js"}
    (tmp_path / "c.js").write_text("export const c = 1, cc = 2;\n")
    assert cycle_in(imports_of(tmp_path)) is None


def test_the_checker_reads_every_import_form(tmp_path):
    for name in "uvwxyz":
        (tmp_path / f"{name}.js").write_text("export const v = 1;\n")
    (tmp_path / "m.js").write_text(
        'import "./u.js";\n'
        "import v from './v.js';\n"
        'import * as w from "./w.js";\n'
        'import { a as b, c } from "./x.js";\n'
        'export * from "./y.js";\n'
        '  export { q } from "../' + tmp_path.name + '/z.js";\n'
        'const s = "import nothing from ./not.js";\n'
    )
    assert imports_of(tmp_path)["m.js"] == {f"{name}.js" for name in "uvwxyz"}
    (tmp_path / "n.js").write_text('import { gone } from "./gone.js";\n')
    with pytest.raises(AssertionError, match="gone.js"):
        imports_of(tmp_path)
