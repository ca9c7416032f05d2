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



def test_vc_run_decodes_in_c_by_default_and_alike_in_numpy(bundle, tmp_path):
    """Where the C decoder is built vc-run uses it, says so in its summary, and finds what numpy's decoder finds."""
    import json

    from dataset_factory import region_camera, sample

    from vc.cli.run import main as vc_run
    from vc.io import write_image

    frames = tmp_path / "frames"
    for index in range(3):
        write_image(frames / f"{index}.png", sample(region_camera(), index).image)
    runs = {}
    for decoder in (None, "numpy"):
        out = tmp_path / str(decoder)
        assert vc_run([str(bundle), str(frames), "-o", str(out), "--quiet",
                       *(["--decoder", decoder] if decoder else [])]) == 0
        assert json.loads((out / "summary.json").read_text())["decoder"] == (decoder or "c")
        runs[decoder] = [json.loads(line)["people"] for line in (out / "detections.jsonl").read_text().splitlines()]
    assert runs[None] == runs["numpy"]


def test_the_c_decoder_where_it_is_not_built_is_refused_by_name(monkeypatch, tmp_path):
    from vc.errors import InputError

    monkeypatch.setenv(native.LIBRARY_VARIABLE, str(tmp_path / "absent.so"))
    assert native.default_decoder() == "numpy"
    with pytest.raises(InputError, match="decoder: the C decoder is not built"):
        native.checked_decoder("c")
    with pytest.raises(InputError, match="decoder: 'cuda' is not one of c, numpy"):
        native.checked_decoder("cuda")
