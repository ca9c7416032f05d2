"""The versions of the packages that decide what a dataset, a checkpoint or a bundle contains (written into
every manifest, so that a result can be traced to the software that made it)."""

from __future__ import annotations

import importlib.metadata

from vc import __version__

VERSIONED_PACKAGES = ("mitsuba", "drjit", "anny", "torch", "numpy", "opencv-python-headless", "openimageio", "onnx",
                      "onnxruntime")


def package_versions() -> dict[str, str]:
    versions = {"visual-compiler": __version__}
    for name in VERSIONED_PACKAGES:
        try:
            versions[name] = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            continue
    return versions
