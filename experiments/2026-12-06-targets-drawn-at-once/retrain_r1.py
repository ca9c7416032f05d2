"""Region r1 of TUD-Stadtmitte's seed-0 compile trained again on its renders with today's codec: are its weights the
compile's, bit for bit? (frozen experiment)

    PYTHONPATH=src python experiments/2026-12-06-targets-drawn-at-once/retrain_r1.py

The compile is expected at /work/runs/tud_s0 (trained at 84da46c, before the change); the new run goes to
/tmp/retrain_r1.
"""

from pathlib import Path

import torch

from vc.stages.config import read_config
from vc.stages.executors import RegionTask, train_region
from vc.stages.train import prepare_training

run, out = Path("/work/runs/tud_s0"), Path("/tmp/retrain_r1")
job = prepare_training(run / "renders", read_config(run / "compile_config.yaml").train, ["r1"])
result = train_region(RegionTask(run / "renders", "r1", job.config, out, job.workers))
new = torch.load(out / "checkpoints" / "r1.pt", weights_only=False)
old = torch.load(run / "run" / "checkpoints" / "r1.pt", weights_only=False)
a, b = old["model"], new["model"]
same = a.keys() == b.keys() and all(torch.equal(a[k], b[k]) for k in a)
print("weights identical:", same, "ap50", result.to_dict().get("ap50"))
