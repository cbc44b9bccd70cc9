"""The pure-torch reference rasterizer against answers worked out by hand (gsplat's conventions)."""

from __future__ import annotations

import math

import pytest
import torch

from engine.render.rasterize_reference import rasterize_reference

K = torch.tensor([[50.0, 0, 16], [0, 50.0, 16], [0, 0, 1]], dtype=torch.float64)
VIEW = torch.eye(4, dtype=torch.float64)


def gaussians(*specs, dtype=torch.float64):
    """specs: (x, y, z, scale, opacity, (r, g, b)); isotropic, identity rotation."""
    means = torch.tensor([s[:3] for s in specs], dtype=dtype)
    quats = torch.tensor([[1.0, 0, 0, 0]] * len(specs), dtype=dtype)
    scales = torch.tensor([[s[3]] * 3 for s in specs], dtype=dtype)
    opacities = torch.tensor([s[4] for s in specs], dtype=dtype)
    colors = torch.tensor([s[5] for s in specs], dtype=dtype)
    return means, quats, scales, opacities, colors


def test_one_isotropic_gaussian_has_the_expected_footprint_colour_and_radius():
    means, quats, scales, opacities, colors = gaussians((0, 0, 2.0, 0.05, 0.8, (1.0, 0.5, 0.2)))
    image, alpha, info = rasterize_reference(means, quats, scales, opacities, colors, VIEW, K, 32, 32)
    var = (0.05 * 50 / 2.0) ** 2 + 0.3  # projected variance in px^2 plus gsplat's 0.3 px blur
    for row, col in [(16, 16), (15, 15), (16, 18), (12, 16)]:
        d2 = (col + 0.5 - 16) ** 2 + (row + 0.5 - 16) ** 2
        expected = 0.8 * math.exp(-0.5 * d2 / var)
        assert alpha[row, col, 0].item() == pytest.approx(expected, rel=1e-6)
        assert image[row, col, :3].tolist() == pytest.approx([expected * c for c in (1.0, 0.5, 0.2)], rel=1e-6)
    extend = min(3.33, math.sqrt(2 * math.log(0.8 * 255)))
    assert info["radii"][0, 0].tolist() == [math.ceil(extend * math.sqrt(var))] * 2
    assert alpha[0, 0, 0] == 0  # far outside the footprint


def test_two_overlapping_gaussians_composite_front_to_back_whatever_their_order():
    front = (0, 0, 2.0, 0.05, 0.6, (1.0, 0.0, 0.0))
    back = (0, 0, 3.0, 0.075, 0.7, (0.0, 0.0, 1.0))  # same projected size as the front one
    image_a, alpha_a, _ = rasterize_reference(*gaussians(front, back), VIEW, K, 32, 32)
    image_b, alpha_b, _ = rasterize_reference(*gaussians(back, front), VIEW, K, 32, 32)
    d2 = 0.5**2 + 0.5**2
    g = math.exp(-0.5 * d2 / ((0.05 * 25) ** 2 + 0.3))
    a1, a2 = 0.6 * g, 0.7 * g
    assert image_a[16, 16, :3].tolist() == pytest.approx([a1, 0.0, (1 - a1) * a2], rel=1e-6)
    assert alpha_a[16, 16, 0].item() == pytest.approx(a1 + (1 - a1) * a2, rel=1e-6)
    assert torch.allclose(image_a, image_b) and torch.allclose(alpha_a, alpha_b)


def test_expected_depth_is_the_alpha_weighted_mean_of_gaussian_depths():
    one, _, _ = rasterize_reference(*gaussians((0.0, 0.0, 2.5, 0.05, 0.9, (1, 1, 1))), VIEW, K, 32, 32)
    assert one[16, 16, -1].item() == pytest.approx(2.5, rel=1e-9)
    front, back = (0, 0, 2.0, 0.05, 0.5, (1, 1, 1)), (0, 0, 4.0, 0.1, 0.5, (1, 1, 1))
    two, alpha, _ = rasterize_reference(*gaussians(front, back), VIEW, K, 32, 32)
    w1 = 0.5 * math.exp(-0.5 * 0.5 / ((0.05 * 25) ** 2 + 0.3))
    w2 = (1 - w1) * 0.5 * math.exp(-0.5 * 0.5 / ((0.1 * 12.5) ** 2 + 0.3))
    assert two[16, 16, -1].item() == pytest.approx((2 * w1 + 4 * w2) / (w1 + w2), rel=1e-6)


def test_gaussians_behind_the_camera_or_off_screen_are_culled():
    specs = [(0, 0, -2.0, 0.05, 0.9, (1, 1, 1)), (5.0, 0, 2.0, 0.05, 0.9, (1, 1, 1)), (0, 0, 2, 0.05, 0.003, (1, 1, 1))]
    image, alpha, info = rasterize_reference(*gaussians(*specs), VIEW, K, 32, 32)
    assert alpha.abs().max() == 0 and (info["radii"] == 0).all()


@pytest.mark.slow
def test_gradients_match_finite_differences():
    specs = [(0.02, -0.01, 2.0, 0.06, 0.6, (0.9, 0.2, 0.1)), (-0.03, 0.02, 2.6, 0.08, 0.7, (0.1, 0.3, 0.8))]
    means, quats, scales, opacities, colors = gaussians(*specs)
    quats = quats + torch.tensor([[0.0, 0.1, -0.2, 0.05], [0.0, -0.1, 0.1, 0.2]], dtype=torch.float64)
    inputs = [t.clone().requires_grad_(True) for t in (means, quats, scales, opacities, colors)]

    def fn(m, q, s, o, c):
        image, alpha, _ = rasterize_reference(m, q, s, o, c, VIEW, K, 32, 32)
        return image

    assert torch.autograd.gradcheck(fn, inputs, eps=1e-6, atol=1e-5, rtol=1e-4)


@pytest.mark.parametrize("classes", [6, 20])
def test_class_logits_blended_directly_equal_classifying_the_blended_identity(classes):
    """render() projects identities through the classifier before blending when that needs fewer channels
    (6 classes) and classifies the blended map otherwise (20): logits and gradients must not change."""
    from engine.io.gaussians import init_from_points, new_classifier
    from engine.render.rasterize import CameraTensors, render

    gen = torch.Generator().manual_seed(0)
    points = torch.rand(60, 3, generator=gen, dtype=torch.float64) * 0.6 - 0.3
    points[:, 2] += 2.0
    base = init_from_points(points.float().numpy(), torch.rand(60, 3, generator=gen).numpy(), 1, 0.5, 0)
    base["identity"] = torch.randn(60, 16, generator=gen)
    camera = CameraTensors(VIEW.float(), K.float(), torch.zeros(3), 32, 32)
    classifier = new_classifier(classes)
    results = []
    for direct in (True, False):
        params = {k: v.clone().requires_grad_(True) for k, v in base.items()}
        out = render(params, camera, 1, classifier=classifier if direct else None, depth=False)
        logits = out.logits if direct else classifier(out.identity)
        weights = torch.rand(logits.shape, generator=torch.Generator().manual_seed(1))
        (logits * weights).sum().backward()
        results.append((logits.detach(), params["identity"].grad, params["means"].grad, out))
    (a, ga, ma, out), (b, gb, mb, _) = results
    assert (out.identity is None) == (classes <= 16) and out.depth is None
    torch.testing.assert_close(a, b, rtol=1e-4, atol=1e-5)
    torch.testing.assert_close(ga, gb, rtol=1e-4, atol=1e-6)
    torch.testing.assert_close(ma, mb, rtol=1e-3, atol=1e-5)


def test_a_view_that_draws_nothing_still_gives_the_2d_means_a_zero_gradient():
    """As gsplat's: DefaultStrategy reads info["means2d"].grad after every backward, also on a view where every
    Gaussian is culled (here all behind the camera)."""
    n = 5
    means = torch.tensor([[0.0, 0.0, -5.0]] * n, requires_grad=True)
    colors = torch.rand(n, 3, requires_grad=True)
    K = torch.tensor([[20.0, 0, 8], [0, 20, 6], [0, 0, 1]])
    image, alpha, info = rasterize_reference(means, torch.tensor([[1.0, 0, 0, 0]] * n), torch.full((n, 3), 0.1),
                                             torch.full((n,), 0.5), colors, torch.eye(4), K, 16, 12)
    info["means2d"].retain_grad()
    (image.sum() + alpha.sum() + colors.sum()).backward()
    assert info["means2d"].grad is not None and not info["means2d"].grad.any()


def test_the_sh_polynomials_blender_shades_with_are_the_engines_basis():
    """engine.formats.splat_ply.SH_POLYNOMIALS (what the add-on's shader nodes evaluate) against
    engine.render.sh.sh_basis on random directions: a sign or exponent copied wrong fails here."""
    from engine.formats.splat_ply import SH_POLYNOMIALS
    from engine.render.sh import sh_basis

    dirs = torch.nn.functional.normalize(torch.randn(50, 3, dtype=torch.float64), dim=-1)
    x, y, z = dirs.unbind(-1)
    table = torch.stack([sum(c * x**a * y**b * z**e for c, (a, b, e) in terms) for terms in SH_POLYNOMIALS], -1)
    assert torch.allclose(table, sh_basis(3, dirs)[:, 1:], atol=1e-12)


def test_views_rendered_together_are_the_views_rendered_one_by_one():
    """A training step renders its views in one rasterization (render_views; gsplat's batched cameras on the
    GPU, checked there by benchmarks/rasterizer_agreement.py): each view's colour (its own SH direction), identity
    logits, depth and alpha are its render alone, and the info holds every view's 2D means."""
    from engine.io.gaussians import init_from_points, new_classifier
    from engine.render.rasterize import CameraTensors, render, render_views

    gen = torch.Generator().manual_seed(0)
    points = torch.rand(60, 3, generator=gen) * 0.6 - 0.3
    points[:, 2] += 2.0
    gaussians = init_from_points(points.numpy(), torch.rand(60, 3, generator=gen).numpy(), 1, 0.5, 0)
    gaussians["identity"] = torch.randn(60, 16, generator=gen)
    gaussians["shN"] = torch.randn(gaussians["shN"].shape, generator=gen) * 0.3  # colour that depends on the view
    cameras = []
    for shift in (-0.2, 0.0, 0.25):
        view = VIEW.float().clone()
        view[0, 3] = shift
        cameras.append(CameraTensors(view, K.float(), -view[:3, :3].T @ view[:3, 3], 32, 32))
    classifier = new_classifier(6)
    together = render_views(gaussians, cameras, 1, classifier=classifier)
    for camera, out in zip(cameras, together, strict=True):
        alone = render(gaussians, camera, 1, classifier=classifier)
        for name in ("rgb", "depth", "alpha", "logits"):
            torch.testing.assert_close(getattr(out, name), getattr(alone, name))
    assert together[0].info["means2d"].shape == (3, 60, 2) and together[0].info["n_cameras"] == 3
    assert not torch.allclose(together[0].rgb, together[2].rgb)
    small = CameraTensors(cameras[0].viewmat, K.float() / 2 + torch.diag(torch.tensor([0.0, 0.0, 0.5])),
                          cameras[0].center, 16, 16)  # another size: each camera alone
    mixed = render_views(gaussians, [cameras[0], small], 1, classifier=classifier)
    assert mixed[1].rgb.shape == (16, 16, 3)
    torch.testing.assert_close(mixed[1].rgb, render(gaussians, small, 1, classifier=classifier).rgb)
    torch.testing.assert_close(mixed[0].rgb, together[0].rgb)
