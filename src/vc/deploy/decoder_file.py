"""The bundle's flat decoder file (``decoder.txt``): what a decoder outside Python needs, readable without a JSON
library (the C decoder's ``vc_bundle_read``, :mod:`vc.deploy.native`).

Written by vc-export beside the manifest, which names it and its SHA-256 like every member. Plain text, one record a
line, a keyword then its values, in this fixed order (version 1)::

    visual-compiler-decoder 1
    frame_size WIDTH HEIGHT
    channels C                       (the heat maps each network emits)
    prior_offsets O1 ... O17         (vc.deploy.decode.UPRIGHT_OFFSETS)
    prior_lower_ankle A
    regions N
    then N times:
    region NAME
    crop_window X0 Y0 WIDTH HEIGHT   (frame pixels)
    input_size WIDTH HEIGHT          (the network's input)
    <each DecodeConfig field> VALUE  (in the dataclass's order; vote_separation may be "none")
    expected_height WIDTH HEIGHT     (heat-map cells), then HEIGHT lines of WIDTH values (input px)
    end

Numbers are written so that they read back exactly: integers as integers, floats as their shortest round-trip
decimal (the expected heights are float32 values, exact as decimals of doubles).
"""

from __future__ import annotations

import io
from dataclasses import fields

import numpy as np

from vc.deploy.decode import UPRIGHT_PRIOR, DecodeConfig, UprightPrior

DECODER_FILE = "decoder.txt"
DECODER_FILE_FORMAT = "visual-compiler-decoder"
DECODER_FILE_VERSION = 1


def _number(value) -> str:
    if value is None:
        return "none"
    if isinstance(value, bool | int | np.integer):
        return str(int(value))
    return repr(float(value))


def decoder_file(manifest: dict, files: dict[str, bytes], prior: UprightPrior = UPRIGHT_PRIOR) -> bytes:
    """The decoder file of a bundle: its ``manifest`` and its member ``files`` (relative name -> bytes; the regions'
    expected-height maps are read from them)."""
    lines = [f"{DECODER_FILE_FORMAT} {DECODER_FILE_VERSION}",
             "frame_size " + " ".join(map(_number, manifest["frame_size"])),
             f"channels {len(manifest['output']['channels'])}",
             "prior_offsets " + " ".join(map(_number, prior.offsets)),
             f"prior_lower_ankle {_number(prior.lower_ankle)}",
             f"regions {len(manifest['regions'])}"]
    for region in manifest["regions"]:
        config = DecodeConfig(**region["decode"])
        heights = np.load(io.BytesIO(files[region["expected_height"]]), allow_pickle=False).astype(np.float32)
        lines += [f"region {region['name']}",
                  "crop_window " + " ".join(map(_number, region["crop_window"])),
                  "input_size " + " ".join(map(_number, region["input_size"])),
                  *(f"{field.name} {_number(getattr(config, field.name))}" for field in fields(DecodeConfig)),
                  f"expected_height {heights.shape[1]} {heights.shape[0]}",
                  *(" ".join(_number(value) for value in row) for row in heights.tolist())]
    lines.append("end")
    return ("\n".join(lines) + "\n").encode()
