"""The benchmarks a user reruns to measure the compiler on their own machine and scenes.

- ``accuracy_vs_time``: what each compile knob buys, accuracy against compile time and runtime, one knob at a time.
- ``effects_ablation``: what the renders' light and camera effects cost to render and buy in accuracy.
- ``model_speed``: training images/s and PyTorch inference ms of each network architecture.
- ``render_throughput``: labelled samples per second per region and spp, and where the render time goes.
- ``runtime_latency``: a bundle's ms per frame and memory per precision, as an appliance runs it.
- ``decode_speed``: decoding time per real frame, the C decoder against numpy's, and whether they agree.
- ``runtime_interleaved``: ms per real frame of several bundles timed frame by frame in one process.
- ``lighting_recovery``: how well the light is recovered from one background rendered under known light.
- ``robustness``: AP50 and false people under COCO-C's corruptions and a camera's everyday changes, beside YOLO-pose.
- ``serve_load``: how many cameras ``vc-serve`` serves on this machine, CPU per camera, latency, memory over a soak.

Each runs from the repository root as ``python -m benchmarks.<name> ...`` (``--help`` lists its arguments) and
writes its numbers and plots to ``benchmarks/results/<name>/`` unless ``--out`` says otherwise
(``benchmarks/README.md``).
"""

from __future__ import annotations

from pathlib import Path

REPOSITORY = Path(__file__).resolve().parents[1]
#: Where the benchmarks write their reports: one folder per benchmark.
RESULTS = REPOSITORY / "benchmarks" / "results"
#: The repository's example scenes (data, not part of the package).
EXAMPLE_SCENES = REPOSITORY / "examples" / "scenes"


def results_folder(name: str) -> Path:
    """The default output folder of the benchmark ``name``: ``benchmarks/results/<name>/``."""
    return RESULTS / name


def display_path(path: Path) -> str:
    """``path`` as a report names it: relative to the repository when inside it, else its name alone. Reports are
    committed and compared across machines; one machine's folders say nothing on another."""
    resolved = Path(path).resolve()
    return str(resolved.relative_to(REPOSITORY)) if resolved.is_relative_to(REPOSITORY) else resolved.name
