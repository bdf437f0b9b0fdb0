"""The package's shape: imports run one way (cli -> live/api -> render -> jobs ->
recipe -> ops, media), no cycles, no private name used outside its module (the size
limits are test_code_limits.py's)."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

pytestmark = pytest.mark.tier("fast")

PACKAGE = Path(__file__).resolve().parent.parent / "marblevideo"

#: Each part's layer: a module may import its own part's modules and lower layers'.
LAYERS = {
    "errors": 0,
    "limits": 0,
    "bundled": 0,
    "version": 0,
    "lazy": 0,
    "cache": 0,
    "media": 1,
    "ops": 1,
    "recipe": 2,
    "motion": 2.5,  # frames -> motion strokes: over the recipe, under the video job
    "jobs": 3,
    "reference": 4,
    "signals": 4,
    "pstmarble": 4,
    "controllers": 5,
    "opencl": 5,
    "outputs": 5,
    "marbler": 6,
    "export": 6,  # a recipe as another host's program: the renderer's packing and sections
    "api": 7,
    "serve": 8,
    "live": 9,
    "scale": 9,
    "design": 10,
    "cli": 11,
    "gallery": 12,
    "__init__": 13,
    "__main__": 13,
}
#: Files and codecs know nothing of recipes and ops: what reaches up from media/
#: (rendering geometry, colours as codes) lives in recipe/.
MEDIA_NEVER_IMPORTS = ("recipe", "ops", "jobs", "opencl", "reference", "marbler")


def _modules() -> dict[str, ast.Module]:
    found = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        found[name] = ast.parse(path.read_text(), str(path))
    return found


MODULES = _modules()


def _imports(tree: ast.Module) -> list[tuple[str, list[str]]]:
    """(module, names) of every ``from marblevideo... import`` and ``import marblevideo...``,
    at any depth (imports inside functions count too)."""
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            if node.module.split(".")[0] == "marblevideo":
                found.append((node.module, [a.name for a in node.names]))
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] == "marblevideo":
                    found.append((alias.name, []))
    return found


def _targets(module: str, names: list[str]) -> list[str]:
    """The package modules an import statement loads."""
    out = [module]
    out += [f"{module}.{n}" for n in names if f"{module}.{n}" in MODULES]
    return [m for m in out if m in MODULES]


def _part(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "__init__"


def _graph() -> dict[str, set[str]]:
    return {
        name: {t for mod, names in _imports(tree) for t in _targets(mod, names)} - {name}
        for name, tree in MODULES.items()
    }


def test_every_part_has_a_layer():
    assert {_part(m) for m in MODULES} <= set(LAYERS), {_part(m) for m in MODULES} - set(LAYERS)


def test_imports_run_one_way():
    wrong = []
    for name, targets in _graph().items():
        for target in targets:
            here, there = _part(name), _part(target)
            if target == "marblevideo" and here in ("__init__", "__main__"):
                continue
            if here != there and LAYERS[there] >= LAYERS[here]:
                wrong.append(f"{name} -> {target}")
    assert not wrong, wrong


def test_media_knows_no_recipe_nor_op():
    wrong = [
        f"{name} -> {target}"
        for name, targets in _graph().items()
        if _part(name) == "media"
        for target in targets
        if _part(target) in MEDIA_NEVER_IMPORTS
    ]
    assert not wrong, wrong


def test_no_import_cycles():
    graph = _graph()
    state: dict[str, int] = {}
    cycles = []

    def visit(node: str, path: list[str]) -> None:
        state[node] = 1
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == 1:
                cycles.append(path[path.index(nxt) :] + [nxt] if nxt in path else [node, nxt])
            elif nxt not in state:
                visit(nxt, [*path, nxt])
        state[node] = 2

    for node in sorted(graph):
        if node not in state:
            visit(node, [node])
    assert not cycles, cycles


def test_no_private_name_is_used_outside_its_module():
    wrong = []
    for name, tree in MODULES.items():
        aliases = {}
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                if node.module.startswith("marblevideo"):
                    for a in node.names:
                        if a.name.startswith("_") and not a.name.startswith("__"):
                            wrong.append(f"{name}: from {node.module} import {a.name}")
                        if f"{node.module}.{a.name}" in MODULES:
                            aliases[a.asname or a.name] = f"{node.module}.{a.name}"
            elif isinstance(node, ast.Import):
                for a in node.names:
                    if a.name.startswith("marblevideo") and a.asname:
                        aliases[a.asname] = a.name
        for node in ast.walk(tree):
            if (
                isinstance(node, ast.Attribute)
                and isinstance(node.value, ast.Name)
                and node.value.id in aliases
                and node.attr.startswith("_")
                and not node.attr.startswith("__")
            ):
                wrong.append(f"{name}: {aliases[node.value.id]}.{node.attr}")
    assert not wrong, wrong
