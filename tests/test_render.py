"""Model-only rendering: outputs, reports, the antialiasing claim of section 3.4, bad input."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from app import render
from model.imageio import read_attrs, read_image


@pytest.mark.parametrize("scene,size", [("zone_plate", 128), ("seascape", 64)])
def test_filtered_closer_to_truth_than_unfiltered(tmp_path, scene, size):
    """Section 3.4: the box-filtered colour table reduces aliasing (zone plate, seascape)."""
    rep = render.render(scene, "full", size, truth=True, truth_ss=8, band_ss=16, out_root=tmp_path, progress=False)
    assert rep["psnr_filtered_vs_truth_db"] > rep["psnr_unfiltered_vs_truth_db"]
    # the band of filter widths above N/8 entries (issue 15), and the truth's own movement
    band = rep["band_w_gt_n8"]
    assert 0 < band["pixels"] < rep["pixels_textured"] or scene == "zone_plate", band
    assert band["psnr_filtered_vs_truth_db"] and band["psnr_unfiltered_vs_truth_db"], band
    tr = rep["truth"]
    assert tr["band_pixels"] == band["pixels"] and tr["ss"] == 8 and tr["band_ss"] == 16
    assert tr["margin_db"]["all"] > 0 and tr["margin_db"]["band"] > 0, tr  # the truth moves less than what it measures
    assert (tmp_path / "truth").is_dir() and Path(tr["cache"]).is_file()
    out = tmp_path / scene / f"full-{size}"
    for name in ("reference.exr", "reference.png", "golden.png", "unfiltered.png", "truth.png", "filter_width.png"):
        assert (out / name).exists(), name
    saved = json.loads((out / "report.json").read_text())
    for key in ("scene", "config", "width", "height", "pixels_textured", "psnr_golden_vs_reference_db",
                "max_abs_error_lsb", "psnr_filtered_vs_truth_db", "psnr_unfiltered_vs_truth_db", "band_w_gt_n8",
                "truth", "seconds"):
        assert key in saved, key
    assert read_image(out / "golden.png").shape == (rep["height"], rep["width"], 4)
    attrs = read_attrs(out / "reference.exr")
    assert attrs.get("tex:scene") == scene and "git" in " ".join(attrs)


def test_texture_interior_figures(tmp_path):
    """The texture interior (model/scene/rim.py): a sphere's silhouette rim carries the coverage error the
    truth averages in; less the rim the figure rises, and the rims cap the figure over all textured pixels."""
    from explore.filters import rim_ceiling

    rep = render.render("marble", "full", 48, truth=True, truth_ss=8, band_ss=16, out_root=tmp_path, progress=False)
    assert 0 < rep["pixels_rim"] and rep["pixels_interior"] + rep["pixels_rim"] == rep["pixels_textured"]
    assert rep["psnr_filtered_vs_truth_interior_db"] > rep["psnr_filtered_vs_truth_db"] + 1, rep  # 2.2 dB at 48 px
    assert rep["psnr_filtered_vs_truth_rim_db"] < rep["psnr_filtered_vs_truth_db"], rep
    # MSE over all >= MSE over the rims x their share: the figure over all cannot pass the rims' cap
    assert rep["psnr_filtered_vs_truth_db"] <= rim_ceiling(rep) + 1e-6
    assert {"pixels_interior", "psnr_filtered_vs_truth_interior_db"} <= set(rep["band_w_gt_n8"])


def test_zone_plate_full_golden_near_reference(tmp_path):
    """full_wide (exact division, 16-bit f and s fractions): within 1 LSB of the reference."""
    rep = render.render("zone_plate", "full_wide", 64, truth=False, out_root=tmp_path, progress=False)
    assert rep["pixels_textured"] == 64 * 64
    assert rep["max_abs_error_lsb"] <= 1.0  # numerics.md: 1/2 LSB of the divider plus f and w quantization


def test_samples_render_their_average(tmp_path):
    """A configuration with sub-pixel samples renders its samples' average (golden.texture_pipeline), not
    the pixel centre: its golden image matches the float reference that samples the same way (full_s4:
    58.7 dB on marble at 32 px; the centre alone, 25.8 dB, is what a render that ignored the samples
    gave) and differs from the one-sample render."""
    from model.hw.config import ROOT

    rep = render.render("marble", str(ROOT / "config" / "candidates" / "full_s4.toml"), 32, truth=False,
                        out_root=tmp_path, progress=False)
    one = render.render("marble", "full", 32, truth=False, out_root=tmp_path, progress=False)
    assert rep["psnr_golden_vs_configured_reference_db"] >= 50.0, rep["psnr_golden_vs_configured_reference_db"]
    assert any("sub-pixel samples" in a for a in rep["approximations"])
    assert rep["psnr_golden_vs_reference_db"] < one["psnr_golden_vs_reference_db"] - 10.0


def test_bad_input_exits_2(capsys):
    assert render.main(["--scene", "no_such_scene", "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert "no_such_scene" in err and "\n" not in err
    assert render.main(["--size", "0"]) == 2
