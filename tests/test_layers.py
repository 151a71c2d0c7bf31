"""Every import between the study's packages points down its layers:

    reference -> contact_model -> records -> engines -> analysis, calibration -> verdict -> report
              -> workflow, benchmarks, postprocess, conformance

(a package imports only itself and the packages of lower layers; packages side by side do not
import each other: analysis and calibration; postprocess holds only the command lines, each
calling the `main` of a module below it). Read from the source with `ast`, so that an import
inside a function or behind `if TYPE_CHECKING` counts too.
"""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
LAYERS = [("reference",), ("contact_model",), ("records",), ("engines",), ("analysis", "calibration"), ("verdict",),
          ("report",), ("workflow", "benchmarks", "postprocess", "conformance")]
LAYER_OF = {package: i for i, packages in enumerate(LAYERS) for package in packages}
#: Where each package's modules are; workflow/scripts import as top-level modules (`common`).
SOURCES = {package: ROOT / package for package in LAYER_OF}


def project_imports(path: Path) -> list[tuple[int, str]]:
    """(line, top-level package) of every import of a study package in a module."""
    tree = ast.parse(path.read_text(), filename=str(path))
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names = [node.module]
        else:
            continue
        found += [(node.lineno, name.split(".")[0]) for name in names if name.split(".")[0] in LAYER_OF]
    return found


def modules():
    for package, folder in SOURCES.items():
        for path in sorted(folder.rglob("*.py")):
            yield package, path


def test_the_layers_cover_every_package_of_the_project():
    packages = {p.parent.name for p in ROOT.glob("*/__init__.py")}
    assert packages <= set(LAYER_OF), f"packages outside the layers: {packages - set(LAYER_OF)}"


@pytest.mark.parametrize("package,path", list(modules()),
                         ids=lambda v: str(v.relative_to(ROOT)) if isinstance(v, Path) else v)
def test_imports_point_down_the_layers(package, path):
    wrong = [f"{path.relative_to(ROOT)}:{line} imports {target} (layer {LAYER_OF[target]}) from {package} "
             f"(layer {LAYER_OF[package]})"
             for line, target in project_imports(path)
             if target != package and LAYER_OF[target] >= LAYER_OF[package]]
    assert not wrong, "\n".join(wrong)


def test_the_check_sees_an_upward_import(tmp_path):
    module = tmp_path / "m.py"
    module.write_text("def f():\n    from verdict.gate import judge\n    import records.files\n")
    assert project_imports(module) == [(2, "verdict"), (3, "records")]
