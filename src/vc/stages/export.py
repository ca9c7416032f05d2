"""The export stage: a finished run as a bundle an appliance embeds (folder or zip, optionally signed, with the
scene's background for scene fitness when the scene is given), loaded back through the runtime's own validation
before it is reported."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from vc.deploy.bundle import Bundle, load_bundle
from vc.deploy.signing import sign_manifest
from vc.model.export import bundle_files, write_bundle
from vc.scenes.loader import Scene
from vc.stages.config import ExportSettings


@dataclass(frozen=True)
class ExportResult:
    manifest: dict
    bundle: Bundle
    size_bytes: int  # of the files inside the bundle


def export(run: Path, output: Path, settings: ExportSettings, as_zip: bool = False,
           signing_key: Path | None = None, show_progress: bool = True, scene: Scene | None = None) -> ExportResult:
    """Measure every precision on held-out renders, keep ``settings.precision``'s model per region and write the
    bundle to ``output`` (complete or not at all); with the run's ``scene``, its scene fitness reference too."""
    if signing_key is not None:
        sign_manifest(b"", signing_key)  # a bad key is refused before the export's work, not after
    manifest, files = bundle_files(run, settings.precision, settings.eval_samples, settings.calibration_samples,
                                   show_progress=show_progress, scene=scene)
    write_bundle(manifest, files, output, as_zip, signing_key)
    return ExportResult(manifest, load_bundle(output), sum(len(data) for data in files.values()))
