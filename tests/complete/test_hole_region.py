"""What a completion may change (engine.complete.hole_region): the Gaussians that render into the hole and nowhere
else, on two cameras looking at a wall, without a trained run."""

from __future__ import annotations

import numpy as np

from engine.capture.scene import Scene
from engine.complete.hole_region import hole_bound
from engine.formats.cameras import Camera

W, H = 40, 30


def camera(name: str, x: float) -> Camera:
    """A camera at (x, 0, -4) looking down +z at the wall z = 0 (OpenCV axes, world = camera rotation)."""
    return Camera(name, W, H, 30.0, 30.0, W / 2, H / 2, np.eye(3), np.array([-x, 0.0, 4.0]))


def scene_of(cameras: list[Camera]) -> Scene:
    images = [np.zeros((H, W, 3), np.uint8) for _ in cameras]
    return Scene(root=".", cameras=cameras, images=images, points=np.zeros((1, 3)), colors=np.zeros((1, 3), np.uint8),
                 train=list(range(len(cameras))), test=[])


def test_only_what_every_view_shows_inside_its_hole_may_change():
    """Left and right cameras, each with a hole around the image centre. A point on the wall straight ahead of
    both holes' overlap is movable; a point the left camera sees outside its hole is fixed; the same point
    hidden from the left camera behind a nearer surface there is movable again; a point no hole contains is
    fixed."""
    cams = [camera("left.png", -0.2), camera("right.png", 0.2)]
    hole = np.zeros((H, W), bool)
    hole[10:20, 14:26] = True  # 12 px wide: +-6 px around the centre, 0.8 world units at the wall
    holes = {0: hole, 1: hole}
    far = {0: np.full((H, W), 4.0), 1: np.full((H, W), 4.0)}  # the wall's depth, seen everywhere
    points = np.array([[0.0, 0.0, 0.0],  # inside both holes
                       [0.65, 0.0, 0.0],  # in the right camera's hole, outside the left one's
                       [2.0, 0.0, 0.0]])  # in no hole
    assert hole_bound(points, scene_of(cams), holes, far).tolist() == [True, False, False]
    hidden = {0: np.full((H, W), 2.0), 1: far[1]}  # the left camera sees a surface at depth 2 in front of the wall
    assert hole_bound(points, scene_of(cams), holes, hidden).tolist() == [True, True, False]


def sheet(x: tuple[float, float], y: tuple[float, float], z: float, opacity: float, step: float = 0.1) -> dict:
    """Round Gaussians (sigma 0.7 x step) on a grid over x by y at depth z: a surface, or a haze in front of one."""
    import torch

    xs, ys = np.meshgrid(np.arange(x[0], x[1] + 1e-9, step), np.arange(y[0], y[1] + 1e-9, step))
    means = torch.tensor(np.stack([xs.ravel(), ys.ravel(), np.full(xs.size, z)], 1), dtype=torch.float32)
    n = len(means)
    return {"means": means, "quats": torch.tensor([[1.0, 0, 0, 0]] * n),
            "scales": torch.full((n, 3), float(np.log(0.7 * step))),
            "opacities": torch.full((n,), float(np.log(opacity / (1 - opacity))))}


def test_a_gaussian_seen_through_haze_outside_the_hole_stays_fixed():
    """The first test's wall seen through a haze halfway to it (a capture's floaters): the haze passes the half
    opacity a render's surface depth takes, so by that depth the left camera would not see the point outside its hole
    and the completion could move it; by occluding_depths the left camera sees it through the haze, and it stays."""
    import torch

    from engine.complete.hole_region import occluding_depths
    from engine.render.rasterize import CameraTensors
    from engine.render.surface_depth import surface_depth

    cams = [camera("left.png", -0.2), camera("right.png", 0.2)]
    wall, haze = sheet((-3.5, 3.5), (-2.5, 2.5), 0.0, 0.99), sheet((-1.5, 1.5), (-1.0, 1.0), -2.0, 0.3)
    removed = {k: torch.cat([wall[k], haze[k]]) for k in wall}
    _, haze_alpha = surface_depth(haze, CameraTensors.from_camera(cams[0], "cpu"), "reference")
    assert 0.5 < float(haze_alpha[H // 2, W // 2]) < 0.9  # see-through, yet past one half
    hole = np.zeros((H, W), bool)
    hole[10:20, 14:26] = True
    holes = {0: hole, 1: hole}
    points = np.array([[0.0, 0.0, 0.0], [0.65, 0.0, 0.0], [2.0, 0.0, 0.0]])
    shown = {i: surface_depth(removed, CameraTensors.from_camera(c, "cpu"), "reference")[0].numpy()
             for i, c in enumerate(cams)}
    assert hole_bound(points, scene_of(cams), holes, shown).tolist() == [True, True, False]  # the haze hid it
    depths = occluding_depths(removed, cams, torch.device("cpu"))
    assert hole_bound(points, scene_of(cams), holes, depths).tolist() == [True, False, False]


def square_hole() -> np.ndarray:
    """A 14 px square around the image centre: +-7 px, 0.93 world units at the wall (7.5 px a unit)."""
    hole = np.zeros((H, W), bool)
    hole[8:22, 13:27] = True
    return hole


def round_gaussians(sigmas: list[float]) -> dict:
    """Round, nearly opaque (0.99) Gaussians of the given sigmas (world units) at the origin, on the wall."""
    import torch

    n = len(sigmas)
    return {"means": torch.zeros(n, 3), "quats": torch.tensor([[1.0, 0, 0, 0]] * n),
            "scales": torch.log(torch.tensor(sigmas))[:, None].repeat(1, 3), "opacities": torch.full((n, 1), 4.6)}


def test_a_gaussian_wider_than_its_hole_is_shrunk_into_it_and_one_that_fits_is_left_alone():
    """A scratch scene paints a small hole with a few Gaussians wider than it; grafted whole they haze the views
    around it, dropped they take the fill with them. fit_to_holes shrinks the wide one until it renders into the
    hole (at most half of where its alpha reaches 0.1 outside it: under 0.1 two pixels past the hole's edge, near
    1 at its centre; unshrunk 0.21 there, and dropped with no shrinking tried) and leaves a small one as it was."""
    import torch

    from engine.complete.hole_region import fit_to_holes
    from engine.render.rasterize import CameraTensors
    from engine.render.rasterize_reference import rasterize_reference

    cams = [camera("left.png", -0.2), camera("right.png", 0.2)]
    hole = square_hole()
    gaussians = round_gaussians([0.1, 0.6])  # 0.75 px and 4.5 px: visible (alpha 0.1) to 1.6 and 9.6 px
    shrunk, fits = fit_to_holes(gaussians, scene_of(cams), {0: hole, 1: hole})
    assert fits.tolist() == [True, True]
    assert torch.equal(shrunk["scales"][0], gaussians["scales"][0])
    factor = float(torch.exp(shrunk["scales"][1, 0] - gaussians["scales"][1, 0]))
    assert 0.3 < factor < 1.0
    for cam in cams:
        view = CameraTensors.from_camera(cam, "cpu")
        _, alpha, _ = rasterize_reference(shrunk["means"][1:], shrunk["quats"][1:], torch.exp(shrunk["scales"][1:]),
                                          torch.sigmoid(shrunk["opacities"][1:, 0]), torch.ones(1, 3), view.viewmat,
                                          view.K, W, H)
        alpha = alpha[..., 0].numpy()
        grown = np.zeros_like(hole)
        grown[6:24, 11:29] = True
        assert alpha[~grown].max() < 0.1 and alpha[hole].max() > 0.9


def test_each_gaussian_keeps_the_largest_scale_factor_at_which_it_fits():
    """fit_to_holes tries the factors from the largest down and each Gaussian only until one fits (the skull capture's
    completion spent most of its time on every factor for every Gaussian): the factor kept is the largest that the
    test of that factor alone passes, for Gaussians that fit at once, after shrinking, and never."""
    import torch

    from engine.complete.hole_region import FIT_LADDER, fit_to_holes

    cams = [camera("left.png", -0.2), camera("right.png", 0.2)]
    holes = {0: square_hole(), 1: square_hole()}
    gaussians = round_gaussians([0.1, 0.4, 0.6, 0.9, 1.3, 40.0])
    gaussians["means"][4] = torch.tensor([0.3, 0.2, 0.0])  # off centre: fits later than its width alone says
    shrunk, fits = fit_to_holes(gaussians, scene_of(cams), holes)
    factors = torch.exp(shrunk["scales"][:, 0] - gaussians["scales"][:, 0]).numpy()
    alone = np.array([fit_to_holes(gaussians, scene_of(cams), holes, ladder=(f,))[1] for f in FIT_LADDER])  # (F, N)
    for k in range(len(factors)):
        passing = [f for f, ok in zip(FIT_LADDER, alone[:, k], strict=True) if ok]
        assert fits[k] == bool(passing)
        if passing:
            assert np.isclose(factors[k], max(passing), rtol=1e-5), (k, factors[k], passing)
    assert fits.tolist()[:2] == [True, True] and not fits[-1] and len(set(np.round(factors[fits], 3))) >= 3


def test_a_removed_gaussian_centred_in_the_hole_but_wider_than_it_stays_fixed():
    """What a completion may change (changeable): centred in the hole and fitting it at its own size. A wide one
    centred there renders past the hole too; changed or dropped, the views around the hole change with it."""
    from engine.complete.hole_region import changeable

    cams = [camera("left.png", -0.2), camera("right.png", 0.2)]
    hole = square_hole()
    far = {0: np.full((H, W), 4.0), 1: np.full((H, W), 4.0)}
    gaussians = round_gaussians([0.1, 0.6, 0.1])
    gaussians["means"][2, 0] = 2.0  # in no hole
    assert changeable(gaussians, scene_of(cams), {0: hole, 1: hole}, far).tolist() == [True, False, False]


def test_a_needle_whose_projection_rounds_to_no_ellipse_fits_no_hole_and_stops_nothing():
    """A Gaussian 1000 units long and 1e-4 across projects to a conic whose determinant float32 rounds below zero
    (the rasterizer culls it). Such Gaussians stopped Ref on three GPU scenes (`linalg.cholesky`: not
    positive-definite); the unbounded direction now reaches past the hole, so it stays fixed."""
    import torch

    from engine.complete.hole_region import changeable

    cams = [camera("left.png", -0.2), camera("right.png", 0.2)]
    hole = square_hole()
    far = {0: np.full((H, W), 4.0), 1: np.full((H, W), 4.0)}
    gaussians = round_gaussians([0.1, 0.1])
    gaussians["scales"][1] = torch.log(torch.tensor([1000.0, 1e-4, 1e-4]))
    turn = torch.tensor([np.cos(0.15), 0.3 * np.sin(0.15), 0.2 * np.sin(0.15), np.sin(0.15)])
    gaussians["quats"][1] = (turn / turn.norm()).float()
    assert changeable(gaussians, scene_of(cams), {0: hole, 1: hole}, far).tolist() == [True, False]
