"""The layering the code keeps: commands parse and report, library functions do the work.

The package is ``src/vc``; its subpackages are the architecture (scenes -> calibration -> render -> model -> deploy
-> serve, measured by evaluation, driven by stages, fronted by cli). No module outside ``vc/cli/`` imports a command
module (a command never runs another's argument parser either: the library stage is there to call), and no function
outside ``vc/cli/`` takes an argparse ``Namespace``. The benchmarks are held to the same rule: they call the stages
with typed settings, as the commands do."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
PACKAGE = REPO / "src" / "vc"
LIBRARY = (PACKAGE, REPO / "benchmarks")
#: What ``src/vc`` holds: one subpackage per part of the compiler, named after its import path.
SUBPACKAGES = {"cli", "scenes", "calibration", "render", "model", "deploy", "evaluation", "stages", "serve"}


def _modules() -> list[Path]:
    return [path for folder in LIBRARY for path in folder.rglob("*.py")]


def _outside_cli(path: Path) -> bool:
    return not path.is_relative_to(PACKAGE / "cli")


def _imported(tree: ast.AST) -> list[str]:
    names = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names += [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module:
            names += [node.module, *(f"{node.module}.{alias.name}" for alias in node.names)]
    return names


def _namespace_parameters(tree: ast.AST) -> list[str]:
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            arguments = node.args.posonlyargs + node.args.args + node.args.kwonlyargs
            for argument in arguments:
                if argument.annotation is not None and "Namespace" in ast.unparse(argument.annotation):
                    found.append(f"{node.name}({argument.arg})")
    return found


def test_the_library_knows_the_layout_it_checks():
    modules = [path for path in _modules() if _outside_cli(path)]
    assert PACKAGE / "stages" / "compile.py" in modules and REPO / "benchmarks" / "accuracy_vs_time.py" in modules
    assert PACKAGE / "cli" / "compile.py" not in modules


def test_the_folders_are_the_import_paths():
    """``src/vc/deploy/decode.py`` is ``vc.deploy.decode``: no package-dir mapping, no code folder outside ``src``."""
    assert {path.name for path in PACKAGE.iterdir() if (path / "__init__.py").is_file()} == SUBPACKAGES
    assert "package-dir" not in (REPO / "pyproject.toml").read_text()
    stray = sorted(path.parent.name for path in REPO.glob("*/__init__.py") if path.parent.name != "benchmarks")
    assert stray == []


def test_no_module_outside_the_commands_imports_one():
    offenders = {str(path.relative_to(REPO)): name for path in _modules() if _outside_cli(path)
                 for name in _imported(ast.parse(path.read_text())) if name == "vc.cli" or name.startswith("vc.cli.")}
    assert offenders == {}


def test_no_function_outside_the_commands_takes_parsed_arguments():
    offenders = {str(path.relative_to(REPO)): found for path in _modules() if _outside_cli(path)
                 if (found := _namespace_parameters(ast.parse(path.read_text())))}
    assert offenders == {}


def test_reading_renders_and_self_testing_a_bundle_load_no_training_or_rendering_engine():
    """The dataset reader sits apart from the torch training stream: reading renders (the self-test, vc-eval)
    must not pay for importing torch, nor for mitsuba."""
    probe = ("import sys, vc.render.dataset, vc.evaluation.selftest, vc.evaluation.renders; "
             "print(sorted({'torch', 'mitsuba', 'drjit', 'anny'} & set(sys.modules)))")
    loaded = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True).stdout
    assert loaded.strip() == "[]"
