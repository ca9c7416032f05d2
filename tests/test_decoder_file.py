"""A bundle's flat decoder file (vc.deploy.decoder_file), as vc-export writes it and the C decoder reads it
(tests/hard_cases/test_native_decode.py reads damaged ones)."""

from __future__ import annotations

import numpy as np
import pytest

from vc.deploy import native

pytestmark = pytest.mark.skipif(not native.available(), reason=f"the C decoder is not built ({native.LIBRARY}: "
                                                               f"make install builds it)")


def test_a_bundles_decoder_file_reads_back_exactly_in_c(bundle):
    """vc-export's decoder.txt, read by the C decoder: every region's window, input, settings, prior and expected
    heights as the manifest and its height maps hold them, to the bit."""
    from vc.deploy.bundle import load_bundle
    from vc.deploy.decode import UPRIGHT_PRIOR

    loaded = load_bundle(bundle)
    assert loaded.manifest["decoder_file"] == "decoder.txt"
    frame_size, regions = native.read_decoder_file(bundle / "decoder.txt")
    assert frame_size == loaded.frame_size and len(regions) == len(loaded.regions)
    for region, entry in zip(regions, loaded.regions, strict=True):
        assert (region.name, region.crop_window, region.input_size) == (entry.name, entry.crop_window,
                                                                      entry.input_size)
        assert region.channels == len(loaded.manifest["output"]["channels"]) and region.config == entry.decode
        np.testing.assert_array_equal(region.prior.offsets, UPRIGHT_PRIOR.offsets)
        assert region.prior.lower_ankle == UPRIGHT_PRIOR.lower_ankle
        np.testing.assert_array_equal(region.expected_height_px, entry.expected_height_px)

