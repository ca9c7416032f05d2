"""ScenePoseNet speed per architecture: training images/s and inference ms per region input.

    python -m benchmarks.model_speed [--arch fast fast-dw ...] [--crop 256 256] [--batch 16] [--steps 4]
                                     [--inputs 1088x272 704x320] [--out benchmarks/results/model_speed]
    python -m benchmarks.model_speed --compute [--threads N] [--out ...]

Training is what ``vc-train`` does per step (forward, the paper's loss with intermediate supervision, backward,
AdamW) on ``--crop`` windows; inference is one eval-mode forward pass of a whole region input in PyTorch (the
exported ONNX runtime is measured by :mod:`benchmarks.runtime_latency`). All cores of this machine (2 on the
reference machine), median of ``--steps`` timed repetitions after one warm-up. The paper architecture (full
resolution, dense 17x17 at 128 channels) would take many minutes per step at these sizes: it is timed once, on
:data:`PAPER_WORKLOAD` for training and on that window for inference. Writes ``model_speed.json``,
``model_speed.md`` and ``model_speed.png`` to ``--out``.

``--compute`` times the default network's training step instead under each of the trainer's compute settings
(``TrainConfig.channels_last``, ``bf16_autocast``), interleaved twice so that a shared machine's drift shows, and
writes ``model_speed_compute.json`` / ``.md`` with the CPU's name and whether it has AMX-BF16 / AVX512-BF16.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import torch  # noqa: E402

from benchmarks import results_folder  # noqa: E402
from vc.cores import cpu_facts, usable_cores  # noqa: E402
from vc.io import write_json  # noqa: E402
from vc.model.config import DEFAULT_ARCH, PRESETS, NetworkConfig  # noqa: E402
from vc.model.loss import scene_pose_loss  # noqa: E402
from vc.model.network import ScenePoseNet  # noqa: E402
from vc.model.trainer import TrainConfig, forward, memory_format  # noqa: E402
from vc.stages.config import TRAINING_COMPUTE  # noqa: E402

#: The demo scene's region inputs (examples/scenes/demo) and PETS09's (examples/scenes/pets09_s2l1).
DEFAULT_INPUTS = ["1088x272", "704x320", "1248x320", "816x304", "528x256"]
#: (window width, height), batch of the paper architecture's one timed training step.
PAPER_WORKLOAD = ((128, 128), 2)


def _median_seconds(run, repetitions: int) -> float:
    run()  # warm-up: allocator, oneDNN primitive caches
    times = []
    for _ in range(repetitions):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return float(np.median(times))


def training_images_per_second(config: NetworkConfig, crop: tuple[int, int], batch: int, repetitions: int,
                               compute: TrainConfig | None = None) -> float:
    """A training step's images/s; ``compute``: the trainer's memory order and autocast (fp32 NCHW when None)."""
    compute = compute or TrainConfig(network=config)
    torch.manual_seed(0)
    net = ScenePoseNet(config).train().to(memory_format=memory_format(compute))
    optimizer = torch.optim.AdamW(net.parameters(), lr=1e-3)
    width, height = crop
    s = config.stem_stride
    images = torch.rand(batch, 3, height, width).contiguous(memory_format=memory_format(compute))
    targets = torch.rand(batch, config.heatmap_channels, height // s, width // s)

    def step() -> None:
        loss, _ = scene_pose_loss(forward(net, images, compute), targets)
        optimizer.zero_grad(set_to_none=True)
        loss.backward()
        optimizer.step()

    return batch / _median_seconds(step, repetitions)


def compare_compute(crop: tuple[int, int], batch: int, steps: int, out: Path) -> None:
    """Time the default network's training step under each compute setting and write model_speed_compute.*."""
    config = PRESETS[DEFAULT_ARCH]
    rates: dict[str, list[float]] = {name: [] for name in TRAINING_COMPUTE}
    for _ in range(2):  # interleaved: drift on a shared machine shows as a spread, not as a bias
        for name, settings in TRAINING_COMPUTE.items():
            compute = TrainConfig(network=config, **settings)
            rates[name].append(training_images_per_second(config, crop, batch, steps, compute))
            print(f"{name}: {rates[name][-1]:.1f} img/s", flush=True)
    cpu, bf16_flags = cpu_facts()
    base = float(np.mean(rates["fp32"]))
    rows = [{"compute": name, "images_per_second": [round(rate, 2) for rate in values],
             "vs_fp32": round(float(np.mean(values)) / base, 2)} for name, values in rates.items()]
    write_json(out / "model_speed_compute.json", {
        "cpu": cpu, "bf16_instructions": bf16_flags, "threads": torch.get_num_threads(), "torch": torch.__version__,
        "arch": DEFAULT_ARCH, "crop": list(crop), "batch": batch, "results": rows})
    lines = [f"Training step of the `{DEFAULT_ARCH}` network ({crop[0]}x{crop[1]} windows, batch {batch}), "
             f"{torch.get_num_threads()} thread(s), {cpu} (bf16 instructions: {', '.join(bf16_flags) or 'none'}); "
             "two interleaved runs each.", "", "| compute | img/s (two runs) | vs fp32 |", "|---|---|---|"]
    lines += [f"| {row['compute']} | {' / '.join(f'{rate:.1f}' for rate in row['images_per_second'])} | "
              f"{row['vs_fp32']:.2f}x |" for row in rows]
    (out / "model_speed_compute.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


@torch.no_grad()
def inference_ms(config: NetworkConfig, size: tuple[int, int], repetitions: int) -> float:
    torch.manual_seed(0)
    net = ScenePoseNet(config).eval()
    image = torch.rand(1, 3, size[1], size[0])
    return 1000.0 * _median_seconds(lambda: net(image), repetitions)


def _size(text: str) -> tuple[int, int]:
    width, height = text.lower().split("x")
    return int(width), int(height)


def _plot(rows: list[dict], inputs: list[str], destination: Path) -> None:
    figure, (left, right) = plt.subplots(1, 2, figsize=(11, 4))
    names = [row["arch"] for row in rows]
    left.barh(names, [row["train_images_per_second"] for row in rows], color="tab:blue")
    left.set(xlabel="training images/s (higher is better)", xscale="log")
    for index, text in enumerate(inputs):
        measured = [row for row in rows if text in row["inference_ms"]]
        right.scatter([row["inference_ms"][text] for row in measured], [row["arch"] for row in measured], label=text,
                      marker="o^sDv"[index % 5])
    right.set(xlabel="inference ms per region input, PyTorch (lower is better)", xscale="log")
    right.legend(fontsize=8)
    for axes in (left, right):
        axes.grid(alpha=0.3, which="both", axis="x")
    figure.suptitle(f"ScenePoseNet speed, {os.cpu_count()} cores")
    figure.tight_layout()
    figure.savefig(destination, dpi=110)
    plt.close(figure)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--arch", nargs="+", default=list(PRESETS), choices=list(PRESETS))
    parser.add_argument("--crop", nargs=2, type=int, default=[256, 256], metavar=("W", "H"))
    parser.add_argument("--batch", type=int, default=16)
    parser.add_argument("--steps", type=int, default=4, help="timed repetitions (the paper: 1)")
    parser.add_argument("--inputs", nargs="+", default=DEFAULT_INPUTS, help="region inputs WxH")
    parser.add_argument("--out", type=Path, default=results_folder("model_speed"))
    parser.add_argument("--compute", action="store_true", help="compare the trainer's compute settings instead")
    parser.add_argument("--threads", type=int, default=usable_cores(), help="torch threads (default: all usable)")
    args = parser.parse_args()
    torch.set_num_threads(args.threads)
    args.out.mkdir(parents=True, exist_ok=True)
    if args.compute:
        compare_compute(tuple(args.crop), args.batch, args.steps, args.out)
        return
    rows = []
    for name in args.arch:
        config = PRESETS[name]
        net = ScenePoseNet(config)
        if name == "paper":
            crop, batch = PAPER_WORKLOAD
            repetitions, inputs = 1, {f"{crop[0]}x{crop[1]}": crop}
        else:
            crop, batch = tuple(args.crop), args.batch
            repetitions, inputs = args.steps, {text: _size(text) for text in args.inputs}
        row = {"arch": name, "default": name == DEFAULT_ARCH, "config": config.to_dict(),
               "parameters": sum(p.numel() for p in net.parameters()), "receptive_field_px": net.receptive_field(),
               "train_window": list(crop), "train_batch": batch,
               "train_images_per_second": round(training_images_per_second(config, crop, batch, repetitions), 3),
               "inference_ms": {text: round(inference_ms(config, size, repetitions), 1)
                                for text, size in inputs.items()}}
        rows.append(row)
        print(json.dumps({key: row[key] for key in ("arch", "train_images_per_second", "inference_ms")}), flush=True)
    args.out.mkdir(parents=True, exist_ok=True)
    write_json(args.out / "model_speed.json", {"cores": os.cpu_count(), "torch": torch.__version__,
                                               "crop": args.crop, "batch": args.batch, "results": rows})
    header = ("| arch | params | receptive field | train window, batch | train img/s | "
              + " | ".join(f"{t} ms" for t in args.inputs) + " |")
    lines = [f"Training: forward, loss, backward, AdamW; inference: one region input, PyTorch eval; "
             f"{os.cpu_count()} cores. The paper architecture is timed on a small window only (minutes per step "
             f"otherwise).", "", header, "|" + "---|" * (5 + len(args.inputs))]
    for row in rows:
        window = f"{row['train_window'][0]}x{row['train_window'][1]}, {row['train_batch']}"
        lines.append(f"| {row['arch']}{' (default)' if row['default'] else ''} | {row['parameters'] / 1e6:.2f} M | "
                     f"{row['receptive_field_px']} px | {window} | {row['train_images_per_second']} | "
                     + " | ".join(str(row["inference_ms"].get(t, "—")) for t in args.inputs) + " |")
    (args.out / "model_speed.md").write_text("\n".join(lines) + "\n")
    _plot(rows, args.inputs, args.out / "model_speed.png")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
