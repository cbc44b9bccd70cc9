"""Object effects (the cast shadow found and relit in 3D, the darkening under an overhang relit, the crater
repainted): hand-built scenes with a worked-out answer, then the removal stage on a tiny run."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import torch

from engine.edit.effects import DETACHED, EffectsConfig, Samples, colors_of, find_shadow, relight
from engine.edit.plane_grid import PlaneFrame
from engine.edit.support_plane import object_core, object_support
from engine.formats.cameras import Camera, pixel_grid
from engine.io.image_io import linear_to_srgb, srgb_to_linear
from tests.gaussian_grids import SPACING, gaussians


def search_of(remaining: dict, removed: dict, samples: Samples, config: EffectsConfig | None = None):
    """find_shadow as `remove` calls it: the object's core and the plane it stands on, up being +z."""
    up = np.array([0.0, 0.0, 1.0])
    core = object_core(removed, up)
    return find_shadow(remaining, core, object_support(remaining["means"].numpy(), core, up), samples,
                       config or EffectsConfig())


def shadow_of(remaining: dict, removed: dict, samples: Samples):
    return search_of(remaining, removed, samples).shadow


def shadow_scene(light: np.ndarray, darken: float = 0.2):
    """A textured floor (z = 0) of Gaussians with a box standing on it (|x|, |y| < 0.15, z < 0.6), and the
    floor Gaussians in the box's shadow under `light` darkened by `darken`: the light they get, so in linear
    values (their colours are sRGB-encoded, as a render's are; 0.2 linear is about 0.5 in sRGB)."""
    xs = np.arange(-1.5, 1.5, SPACING)
    floor = np.stack(np.meshgrid(xs, xs, indexing="ij"), -1).reshape(-1, 2)
    floor = np.concatenate([floor, np.zeros((len(floor), 1))], 1)
    checker = ((np.floor(floor[:, 0] / 0.2) + np.floor(floor[:, 1] / 0.2)) % 2).astype(bool)
    lit = np.where(checker[:, None], [0.8, 0.7, 0.6], [0.55, 0.6, 0.5])
    # a floor point is in shadow when its ray towards the light passes through the box
    t = np.linspace(0, 0.6 / light[2], 200)
    ray = floor[:, None, :] + t[None, :, None] * light
    in_box = (np.abs(ray[..., 0]) < 0.15) & (np.abs(ray[..., 1]) < 0.15) & (ray[..., 2] < 0.6)
    shadowed = in_box.any(1) & ~((np.abs(floor[:, 0]) < 0.15) & (np.abs(floor[:, 1]) < 0.15))
    seen = np.where(shadowed[:, None], linear_to_srgb(srgb_to_linear(lit) * darken), lit)
    bx = np.arange(-0.14, 0.15, SPACING)
    box = np.stack(np.meshgrid(bx, bx, np.arange(0.02, 0.6, SPACING), indexing="ij"), -1).reshape(-1, 3)
    return floor, lit, seen, shadowed, box


def view_samples(floor: np.ndarray, seen: np.ndarray, hidden: np.ndarray | None = None) -> Samples:
    """What the views show of shadow_scene's floor: four jittered samples a floor Gaussian (colours `seen`), none
    under the box, where no view sees, nor under the floor Gaussians `hidden` (bool, by floor Gaussian)."""
    jitter = np.random.default_rng(0).uniform(-SPACING / 2, SPACING / 2, (4 * len(floor), 3)) * [1, 1, 0]
    points, colors = np.repeat(floor, 4, 0) + jitter, np.repeat(seen, 4, 0)
    seen_by_views = ~((np.abs(points[:, 0]) < 0.15) & (np.abs(points[:, 1]) < 0.15))
    if hidden is not None:
        seen_by_views &= ~np.repeat(hidden, 4)
    return Samples(points=points[seen_by_views], colors=colors[seen_by_views])


def sun(azimuth: float) -> np.ndarray:
    """The light 40 degrees above shadow_scene's floor (z = 0) from `azimuth` degrees, as find_shadow's frame
    builds its candidates."""
    return PlaneFrame(n=np.array([0.0, 0.0, 1.0]), a=np.array([1.0, 0.0, 0.0]), b=np.array([0.0, 1.0, 0.0]),
                      d=0.0).light(40.0, azimuth)


def test_a_cast_shadow_is_found_from_the_views_and_relit_to_the_surface_around_it():
    floor, lit, seen, truth, box = shadow_scene(sun(30))
    remaining = gaussians(floor, seen)
    removed = gaussians(box, np.full((len(box), 3), 0.9))
    shadow = shadow_of(remaining, removed, view_samples(floor, seen))
    assert shadow is not None
    found = shadow.shadowed & (np.abs(floor[:, 0]) < 1.4) & (np.abs(floor[:, 1]) < 1.4)
    iou = (found & truth).sum() / (found | truth).sum()
    assert iou > 0.8, shadow.report()
    assert shadow.elevation == pytest.approx(40, abs=6)
    np.testing.assert_allclose(shadow.gain, 1 / 0.2, rtol=0.15)  # of light: 1 / darken
    after = colors_of(relight(remaining, shadow))
    core = truth & shadow.shadowed
    assert np.abs(after[core] - lit[core]).mean() < 0.1 * np.abs(seen[core] - lit[core]).mean() + 0.02
    assert np.allclose(after[~shadow.shadowed], seen[~shadow.shadowed])


@pytest.mark.parametrize("azimuth", [30, 75, 120])
def test_the_shadows_gain_is_the_lights_in_every_channel_whatever_share_of_the_texture_each_side_holds(azimuth):
    """The lit edge and the shadow hold the checker's two colours in shares that change with the light's
    direction; per-channel medians jumped between the two colours there (gains [2.18 3.55 3.36] at 75 degrees
    for the true 5: the relit shadow came out with a colour cast)."""
    floor, lit, seen, truth, box = shadow_scene(sun(azimuth))
    shadow = shadow_of(gaussians(floor, seen), gaussians(box, np.full((len(box), 3), 0.9)), view_samples(floor, seen))
    assert shadow is not None
    np.testing.assert_allclose(shadow.gain, 1 / 0.2, rtol=0.1)
    assert shadow.gain.max() / shadow.gain.min() < 1.05, shadow.gain


@pytest.mark.parametrize("azimuth", [30, 75])
def test_the_gain_is_measured_past_the_shadows_soft_edge(azimuth):
    """A shadow whose edge fades over two Gaussians (a sun's penumbra, and the blur of a render trained from few
    views): the lit samples the gain is measured on lie past the fade, so the gain is the light's (measured next to
    the edge it was 4.1-4.4 for the true 5; on tiny CPU runs the found gain was 0.66-0.93 of the truth's)."""
    floor, lit, seen, truth, box = shadow_scene(sun(azimuth))
    apart = np.sqrt(((floor[~truth, None, :2] - floor[None, truth, :2]) ** 2).sum(-1)).min(1)
    light = np.full(len(floor), 0.2)
    light[~truth] = np.minimum(0.2 + 0.8 * apart / (2 * SPACING), 1.0)
    seen = linear_to_srgb(srgb_to_linear(lit) * light[:, None])
    shadow = shadow_of(gaussians(floor, seen), gaussians(box, np.full((len(box), 3), 0.9)), view_samples(floor, seen))
    assert shadow is not None
    np.testing.assert_allclose(shadow.gain, 1 / 0.2, rtol=0.08)


@pytest.mark.parametrize("azimuth", [30, 75])
def test_with_soft_edge_a_penumbra_is_relit_by_how_dark_it_is_not_all_or_nothing(azimuth):
    """A sun's penumbra six Gaussians wide across the shadow's outline: relit all or nothing, its half-dark
    Gaussians come out too bright or left dark (the light and dark line along held-out statue_s101's relit shadow);
    by their samples' darkness, near the lit floor's colours."""
    floor, lit, _, truth, box = shadow_scene(sun(azimuth))
    apart = np.sqrt(((floor[:, None, :2] - floor[None, truth, :2]) ** 2).sum(-1)).min(1)  # 0 inside
    inward = np.sqrt(((floor[:, None, :2] - floor[None, ~truth, :2]) ** 2).sum(-1)).min(1)  # 0 outside
    signed = np.where(truth, -inward, apart)  # distance past the outline
    light = np.clip(0.6 + 0.8 * signed / (6 * SPACING), 0.2, 1.0)
    seen = linear_to_srgb(srgb_to_linear(lit) * light[:, None])
    remaining, removed = gaussians(floor, seen), gaussians(box, np.full((len(box), 3), 0.9))
    penumbra = (light > 0.3) & (light < 0.9) & (np.abs(floor[:, :2]) < 1.4).all(1)
    errors = {}
    for soft in (False, True):
        shadow = search_of(remaining, removed, view_samples(floor, seen), EffectsConfig(soft_edge=soft)).shadow
        assert shadow is not None
        errors[soft] = np.abs(colors_of(relight(remaining, shadow))[penumbra] - lit[penumbra]).mean()
    assert errors[True] < 0.8 * errors[False], errors  # 0.056 and 0.056 against 0.077 and 0.075


def test_the_shadow_another_object_casts_inside_the_objects_is_left_dark():
    """A post standing in the box's shadow: without the box its own shadow is still there (gt/ has it), so the
    support in it is left as it was while the rest of the box's shadow is relit."""
    light = sun(30)
    floor, lit, seen, truth, box = shadow_scene(light)
    centre = -0.45 * light[:2] / np.linalg.norm(light[:2])  # 0.45 from the box, away from the light
    px = np.arange(-0.04, 0.05, SPACING / 2)
    post = np.stack(np.meshgrid(px, px, np.arange(0.02, 0.3, SPACING / 2), indexing="ij"), -1).reshape(-1, 3)
    post[:, :2] += centre
    t = np.linspace(0, 0.3 / light[2], 100)
    ray = floor[:, None, :] + t[None, :, None] * light
    under_post = (np.abs(floor[:, :2] - centre) < 0.05).all(1)
    theirs_truth = ((np.abs(ray[..., :2] - centre) < 0.05).all(-1) & (ray[..., 2] < 0.3)).any(1) & ~under_post
    both = truth & theirs_truth
    assert both.sum() > 20  # the post's shadow reaches into the box's
    remaining = gaussians(np.concatenate([floor, post]), np.concatenate([seen, np.full((len(post), 3), 0.3)]))
    others = np.concatenate([np.zeros(len(floor), bool), np.ones(len(post), bool)])
    samples = view_samples(floor, seen, under_post)
    up = np.array([0.0, 0.0, 1.0])
    core = object_core(gaussians(box, np.full((len(box), 3), 0.9)), up)
    plane = object_support(remaining["means"].numpy(), core, up)
    unaware = find_shadow(remaining, core, plane, samples, EffectsConfig()).shadow
    shadow = find_shadow(remaining, core, plane, samples, EffectsConfig(), others).shadow
    assert unaware is not None and shadow is not None
    n = len(floor)
    assert unaware.shadowed[:n][both].mean() > 0.8  # relit with the box's shadow when the post is not known
    # (at the grid's resolution: a cell the post's shadow only grazes stays with the box's)
    assert shadow.theirs[:n][both].mean() > 0.8 and shadow.shadowed[:n][both].mean() < 0.2
    after = colors_of(relight(remaining, shadow))[:n]
    kept = both & shadow.theirs[:n]
    np.testing.assert_allclose(after[kept], seen[kept], atol=1e-5)
    assert not (shadow.shadowed & shadow.theirs).any()
    rest = truth & ~theirs_truth
    found = shadow.shadowed[:n] & (np.abs(floor[:, 0]) < 1.4) & (np.abs(floor[:, 1]) < 1.4)
    assert (found & rest).sum() / (found | rest).sum() > 0.8
    assert np.abs(after[rest & found] - lit[rest & found]).mean() < 0.05


@pytest.mark.parametrize(("offset", "half_width"), [(0.13, 0.1), (-0.12, 0.07)])
def test_a_shadow_band_from_out_of_view_that_crosses_the_objects_is_left_dark(offset, half_width):
    """A tree the views never show casts a band along the sun's direction across the floor, through half of
    the box's shadow (statue_s100: a trunk's band across the slab, relit with the statue's shadow, and every
    fill painted a lit slab there). No Gaussian casts it, so only the views can say: it is dark on past both
    ends of the box's shadow. The band stays as it was, the rest of the box's shadow is relit. A band along the
    light rewards a longer cast: the first of these (two thirds of the shadow's width) pulled the light's search
    to 20 degrees for the true 40 until the lines dark past the box's sunlit side were kept out of it."""
    light = sun(30)
    floor, lit, seen, truth, box = shadow_scene(light)
    u = light[:2] / np.linalg.norm(light[:2])
    across = floor[:, :2] @ np.array([-u[1], u[0]])  # distance across the sun's direction from the box's centre
    band = np.abs(across - offset) < half_width  # the box's shadow is 0.3 wide
    seen = np.where((band & ~truth)[:, None], linear_to_srgb(srgb_to_linear(lit) * 0.2), seen)
    remaining = gaussians(floor, seen)
    shadow = shadow_of(remaining, gaussians(box, np.full((len(box), 3), 0.9)), view_samples(floor, seen))
    assert shadow is not None
    both, rest = truth & band, truth & ~band
    assert both.sum() > 50 and rest.sum() > 50
    assert shadow.elevation == pytest.approx(40, abs=6), shadow.report()
    core = truth & (np.abs(across - offset) < half_width - SPACING)  # a Gaussian the band's edge grazes may go
    assert shadow.shadowed[core].mean() < 0.2 and shadow.theirs[core].mean() > 0.8, shadow.report()
    after = colors_of(relight(remaining, shadow))
    np.testing.assert_allclose(after[both & shadow.theirs], seen[both & shadow.theirs], atol=1e-5)
    found = shadow.shadowed & (np.abs(floor[:, 0]) < 1.4) & (np.abs(floor[:, 1]) < 1.4)
    assert (found & rest).sum() / (found | rest).sum() > 0.7, shadow.report()
    assert np.abs(after[rest & found] - lit[rest & found]).mean() < 0.05
    np.testing.assert_allclose(shadow.gain, 1 / 0.2, rtol=0.15)


@pytest.mark.parametrize("turn", [0, 90, 120, 270])
def test_darkness_beyond_a_lit_stretch_beside_the_object_is_not_its_shadow(turn):
    """A dark patch on the floor 0.6 from the box's centre, `turn` degrees round from the sun's side, with lit
    floor between: a long cast from a low light reaches it past the lit stretch and, being larger, outscored the
    box's own shadow (statue_s8 on one H200: a 15-degree light over the slab's dark blotches and the tree's shadow
    on the grass, relit to white blobs). A shadow on the floor starts at the object, so the light found is the
    box's and the patch stays dark."""
    light = sun(30)
    floor, lit, seen, truth, box = shadow_scene(light)
    a = np.radians(30 + turn)
    towards = np.array([np.cos(a), np.sin(a)])
    along, across = floor[:, :2] @ towards, floor[:, :2] @ np.array([-towards[1], towards[0]])
    patch = (along > 0.6) & (np.abs(across) < 0.5) & ~truth
    seen = np.where(patch[:, None], linear_to_srgb(srgb_to_linear(lit) * 0.2), seen)
    shadow = shadow_of(gaussians(floor, seen), gaussians(box, np.full((len(box), 3), 0.9)), view_samples(floor, seen))
    assert shadow is not None
    assert shadow.elevation == pytest.approx(40, abs=6), shadow.report()
    found = shadow.shadowed & (np.abs(floor[:, 0]) < 1.4) & (np.abs(floor[:, 1]) < 1.4)
    assert (found & truth).sum() / (found | truth).sum() > 0.8, shadow.report()
    assert shadow.shadowed[patch].mean() < 0.05


def test_no_shadow_is_claimed_where_a_band_from_out_of_view_runs_through_the_object():
    """The box stands inside a tree's band, twice as wide as its shadow, running along the sun's direction on
    both sides of it: its own shadow falls where the tree's already does, so without the box the floor looks the
    same (held-out statue_s100: a trunk's band through the statue, and a low sun's cast along it was relit as
    the statue's shadow, the fill then painting lit slab into the band). A light from the other side finds the
    band as dark, so there is nothing to relight, and no contact shade is looked for (`surrounded`: relit to the
    band's level, the contact shade cost held-out statue_s100 2.7 dB of Ref-telea's m-PSNR on an H200)."""
    light = sun(30)
    floor, lit, _, truth, box = shadow_scene(light)
    u = light[:2] / np.linalg.norm(light[:2])
    band = np.abs(floor[:, :2] @ np.array([-u[1], u[0]])) < 0.3  # the box's shadow is 0.3 wide
    assert truth[band].mean() > 0 and not truth[~band].any()
    seen = np.where(band[:, None], linear_to_srgb(srgb_to_linear(lit) * 0.2), lit)
    search = search_of(gaussians(floor, seen), gaussians(box, np.full((len(box), 3), 0.9)), view_samples(floor, seen))
    assert search.shadow is None, search.report()
    assert search.verdict == "a light 90+ degrees away about as dark: the darkness surrounds the object"
    assert search.surrounded


def test_no_shadow_is_claimed_where_the_surface_around_the_object_is_evenly_lit():
    floor, lit, _, _, box = shadow_scene(np.array([0.0, 0.6, 0.8]))
    rng = np.random.default_rng(1)
    samples = Samples(points=floor, colors=lit * rng.uniform(0.95, 1.05, lit.shape))
    search = search_of(gaussians(floor, lit), gaussians(box, np.full((len(box), 3), 0.9)), samples)
    assert search.shadow is None
    assert search.verdict == DETACHED and search.report()["receivers"] > 200  # no candidate's cast starts dark
    assert not search.surrounded  # the contact shade is looked for


def overhang_scene(darken: float):
    """A floor (z = 0) of Gaussians striped finer than the shading window, a ball of radius 0.4 resting on it at
    the origin, and the floor under and beside the ball darkened by `darken` (to r = 0.4, fading out by 0.6):
    the sky the ball hid, in linear values. Returns the floor, its lit and its seen colours (sRGB-encoded), and
    the ball's points."""
    xs = np.arange(-1.5, 1.5, SPACING / 2)
    floor = np.stack(np.meshgrid(xs, xs, indexing="ij"), -1).reshape(-1, 2)
    floor = np.concatenate([floor, np.zeros((len(floor), 1))], 1)
    lit = np.where((np.floor(floor[:, 0] / 0.06) % 2 == 1)[:, None], [0.8, 0.6, 0.5], [0.6, 0.45, 0.4])
    r = np.linalg.norm(floor[:, :2], axis=1)
    shade = 1 - (1 - darken) * np.clip((0.6 - r) / 0.2, 0, 1)
    rng = np.random.default_rng(0)
    ball = rng.normal(size=(3000, 3))
    ball = 0.4 * ball / np.linalg.norm(ball, axis=1, keepdims=True) + [0.0, 0.0, 0.4]
    return floor, lit, linear_to_srgb(srgb_to_linear(lit) * shade[:, None]), ball


def ball_with_cast(light: np.ndarray, darken: float, cast: float):
    """overhang_scene's ball and floor (the floor under and beside the ball darkened by `darken`), and its cast
    shadow past its outline under `light`, darkened by `cast` (linear): the floor, its seen colours, the ball, the
    floor Gaussians in the cast, and the views' samples (none where the ball touches the floor)."""
    floor, _, seen, ball = overhang_scene(darken)
    ahead = (floor - [0.0, 0.0, 0.4]) @ light  # a floor point's ray towards the light meets the ball
    miss = ahead ** 2 - ((floor - [0.0, 0.0, 0.4]) ** 2).sum(1) + 0.16
    r = np.linalg.norm(floor[:, :2], axis=1)
    in_cast = (miss > 0) & (-ahead - np.sqrt(np.maximum(miss, 0)) > 0) & (r > 0.4)
    seen = np.where(in_cast[:, None], linear_to_srgb(srgb_to_linear(seen) * cast), seen)
    return floor, seen, ball, in_cast, Samples(points=floor[r > 0.08], colors=seen[r > 0.08])


@pytest.mark.parametrize("elevation, darken, cast", [(40, 0.25, 0.55), (50, 0.35, 0.7)])
def test_the_darkness_under_a_round_objects_outline_does_not_hide_its_cast_shadow(elevation, darken, cast):
    """A ball's outline overhangs the floor, and grazing views see the floor under it dark whatever the light:
    counted, it made every candidate's cast dark and lights 90+ degrees away as dark as the true one, so the
    shadow was left as 'surrounded' (held-out livingroom_s100, the snowman, on an H200). Judged past the outline,
    the cast shadow is found and relit."""
    light = PlaneFrame(n=np.array([0.0, 0.0, 1.0]), a=np.array([1.0, 0.0, 0.0]), b=np.array([0.0, 1.0, 0.0]),
                       d=0.0).light(elevation, 30)
    floor, seen, ball, in_cast, samples = ball_with_cast(light, darken, cast)
    search = search_of(gaussians(floor, seen), gaussians(ball, np.full((len(ball), 3), 0.9)), samples)
    assert search.verdict == "found", search.report()
    assert search.report()["darkest_elsewhere"] < 0.2
    assert search.shadow.shadowed[in_cast].mean() > 0.4, search.report()
    far = np.linalg.norm(floor[:, :2], axis=1) > 1.0
    assert not search.shadow.shadowed[far & ~in_cast].any()


def test_the_darkening_under_an_overhang_is_relit_to_the_floor_around_it_texture_kept():
    from engine.edit.contact_shade import find_contact_shade
    from engine.edit.effects import brighten

    floor, lit, seen, ball = overhang_scene(darken=0.2)
    up = np.array([0.0, 0.0, 1.0])
    core = object_core(gaussians(ball, np.full((len(ball), 3), 0.9)), up)
    remaining = gaussians(floor, seen)
    plane = object_support(floor, core, up)
    found = find_contact_shade(remaining, core, plane, Samples(floor, seen), EffectsConfig())
    assert found is not None
    r = np.linalg.norm(floor[:, :2], axis=1)
    after = colors_of(brighten(remaining, found.shaded, found.gains))
    inner = r < 0.35
    assert np.abs(after[inner] - lit[inner]).mean() < 0.25 * np.abs(seen[inner] - lit[inner]).mean()
    stripes = np.corrcoef(after[inner, 0], lit[inner, 0])[0, 1]
    assert stripes > 0.9  # the texture came back, not a flat average
    far = r > 1.2
    assert not found.shaded[far].any() and np.allclose(after[far], seen[far])
    assert found.weight[inner[found.shaded]].mean() > 0.9  # the effect masks take it


def test_the_darkenings_gain_stays_under_the_configured_most():
    """`remove --contact-most` bounds the darkening's relight (a judge variant): the overhang's floor, five times
    darker under it, asks for more than 1.5 ** 2.4 of light and gets no more."""
    from engine.edit.contact_shade import find_contact_shade

    floor, _, seen, ball = overhang_scene(darken=0.2)
    up = np.array([0.0, 0.0, 1.0])
    core = object_core(gaussians(ball, np.full((len(ball), 3), 0.9)), up)
    remaining, plane = gaussians(floor, seen), object_support(floor, core, up)
    free = find_contact_shade(remaining, core, plane, Samples(floor, seen), EffectsConfig())
    bound = find_contact_shade(remaining, core, plane, Samples(floor, seen), EffectsConfig(contact_most=1.5))
    assert free.gains.max() > 1.5 ** 2.4 + 0.1, free.gains.max()
    assert bound.gains.max() <= 1.5 ** 2.4 + 1e-5, bound.gains.max()


def test_a_lit_layer_under_an_overhang_is_not_relit_past_the_lit_floor():
    """Where a cell is dark, one of its layers may be lit already (a surface other layers darken): the cell's gain
    lifted such Gaussians past the lit floor, a pale ring round the contact (tuning livingroom_s90, on an H200 and
    on a tiny CPU run). Each Gaussian's gain stops at its cell's lit level times the lit floor's spread; the dark
    layer is relit as before."""
    from engine.edit.contact_shade import find_contact_shade
    from engine.edit.effects import brighten

    floor, lit, seen, ball = overhang_scene(darken=0.2)
    inner = np.linalg.norm(floor[:, :2], axis=1) < 0.35
    points = np.concatenate([floor, floor[inner] + [0.0, 0.0, 0.002]])  # a lit layer over the dark one
    colours = np.concatenate([seen, lit[inner]])
    up = np.array([0.0, 0.0, 1.0])
    core = object_core(gaussians(ball, np.full((len(ball), 3), 0.9)), up)
    remaining = gaussians(points, colours)
    found = find_contact_shade(remaining, core, object_support(floor, core, up), Samples(floor, seen), EffectsConfig())
    assert found is not None
    after = colors_of(brighten(remaining, found.shaded, found.gains))
    layer = np.arange(len(points)) >= len(floor)
    assert after[layer].max() <= lit.max() + 0.02, after[layer].max()  # without the ceiling: 1.64
    dark = np.arange(len(points)) < len(floor)
    assert np.abs(after[dark & np.r_[inner, np.zeros(layer.sum(), bool)]] - lit[inner]).mean() < \
        0.25 * np.abs(seen[inner] - lit[inner]).mean()


def test_a_band_running_on_past_the_darkening_is_left_dark_the_darkening_beside_it_relit():
    """A tree's band (|y| < 0.2) crosses the floor through the ball: dark on past the darkening's reach on both
    sides, so the ball did not cast it and gt/ keeps it (held-out statue_s100: the band beside the statue was
    relit as its contact shade). The band's cells by the ball are relit to the band's own level, not to the lit
    floor: the ball's darkening goes, the band stays (held-out statue_s100 again: left as it was, the darkening
    in the band was spread into the hole as a dark block); the band away from the ball stays as seen; the
    darkening elsewhere is relit to the floor. Unless the darkness is the ball's own cast shadow (`cast`), which
    the contact shade finishes relighting."""
    from engine.edit.contact_shade import find_contact_shade
    from engine.edit.effects import brighten

    floor, lit, seen, ball = overhang_scene(darken=0.2)
    band = np.abs(floor[:, 1]) < 0.2
    seen = np.where(band[:, None], linear_to_srgb(srgb_to_linear(seen) * 0.2), seen)
    in_band = linear_to_srgb(srgb_to_linear(lit) * 0.2)  # the truth there: the band without the darkening
    up = np.array([0.0, 0.0, 1.0])
    core = object_core(gaussians(ball, np.full((len(ball), 3), 0.9)), up)
    remaining = gaussians(floor, seen)
    found = find_contact_shade(remaining, core, object_support(floor, core, up), Samples(floor, seen),
                               EffectsConfig())
    assert found is not None
    after = colors_of(brighten(remaining, found.shaded, found.gains))
    x, y, r = floor[:, 0], floor[:, 1], np.linalg.norm(floor[:, :2], axis=1)
    by_ball = (np.abs(y) < 0.1) & (np.abs(x) > 0.45) & (np.abs(x) < 0.6)
    error, was = np.abs(after[by_ball] - in_band[by_ball]).mean(), np.abs(seen[by_ball] - in_band[by_ball]).mean()
    assert by_ball.sum() > 100 and error < 0.35 * was, (error, was)
    away = (np.abs(y) < 0.1) & (np.abs(x) > 0.75)
    assert np.abs(after[away] - seen[away]).max() < 1e-5
    beside = (r < 0.35) & (np.abs(y) > 0.3)
    assert np.abs(after[beside] - lit[beside]).mean() < 0.25 * np.abs(seen[beside] - lit[beside]).mean()
    # the same darkness as the object's own cast shadow (relit before, its rim left): relit as its contact shade
    own = find_contact_shade(remaining, core, object_support(floor, core, up), Samples(floor, seen), EffectsConfig(),
                             cast=band)
    assert own.shaded[by_ball].all() and (own.gains[by_ball[own.shaded]] > 1.5).all()


def test_a_band_wider_than_the_object_is_left_dark_round_it():
    """A tree's band (|y| < 0.55) wider than the ball (radius 0.4) crosses the floor through it: straight out from
    the ball across the band, the lit floor lies past the zone, so each direction's ring says the darkness ends
    there, and the band round the ball was relit to the lit floor (held-out statue_s100 at c36679a, training seed
    1: 4,474 Gaussians of the band beside the statue relit by up to 3.4x, a lit bay in it in every view). Along
    the band, its darkness runs on past the zone at both ends of a line through the cell: the band's cells there
    keep the band's level; the ball's darkening in the band is relit to it."""
    from engine.edit.contact_shade import find_contact_shade
    from engine.edit.effects import brighten

    floor, lit, seen, ball = overhang_scene(darken=0.2)
    band = np.abs(floor[:, 1]) < 0.55
    seen = np.where(band[:, None], linear_to_srgb(srgb_to_linear(seen) * 0.2), seen)
    in_band = linear_to_srgb(srgb_to_linear(lit) * 0.2)
    up = np.array([0.0, 0.0, 1.0])
    core = object_core(gaussians(ball, np.full((len(ball), 3), 0.9)), up)
    remaining = gaussians(floor, seen)
    found = find_contact_shade(remaining, core, object_support(floor, core, up), Samples(floor, seen),
                               EffectsConfig())
    after = seen if found is None else colors_of(brighten(remaining, found.shaded, found.gains))
    r = np.linalg.norm(floor[:, :2], axis=1)
    near = band & (r < 0.7)  # the band within the darkening's reach: without the lines, relit past the truth
    error, was = np.abs(after[near] - in_band[near]).mean(), np.abs(seen[near] - in_band[near]).mean()
    assert error < 0.35 * was, (error, was)  # without: 0.098 against 0.084
    away = band & (r > 0.9)
    assert np.abs(after[away] - seen[away]).max() < 1e-5


def test_no_darkening_is_claimed_under_an_object_that_cast_none():
    from engine.edit.contact_shade import find_contact_shade

    floor, lit, _, ball = overhang_scene(darken=1.0)
    up = np.array([0.0, 0.0, 1.0])
    core = object_core(gaussians(ball, np.full((len(ball), 3), 0.9)), up)
    assert find_contact_shade(gaussians(floor, lit), core, object_support(floor, core, up), Samples(floor, lit),
                              EffectsConfig()) is None


def crater_scene():
    """overhang_scene's striped floor and ball, undarkened, with the floor under one half of the ball sunk 0.06
    below its plane and dark (what grazing views build there) and under the other half on the plane as it was
    (what views saw well). Returns the floor, its lit and seen colours, the ball's points and which are sunk."""
    floor, lit, _, ball = overhang_scene(darken=1.0)
    sunk = (np.linalg.norm(floor[:, :2], axis=1) < 0.25) & (floor[:, 0] < 0)
    floor, seen = floor.copy(), lit.copy()
    floor[sunk, 2], seen[sunk] = -0.06, 0.15
    return floor, lit, seen, ball, sunk


def crater_underside(floor: np.ndarray, seen: np.ndarray, ball: np.ndarray, config: EffectsConfig,
                     others: np.ndarray | None = None):
    from engine.edit.underside import find_underside

    up = np.array([0.0, 0.0, 1.0])
    core = object_core(gaussians(ball, np.full((len(ball), 3), 0.9)), up)
    return find_underside(gaussians(floor, seen), core, object_support(floor, core, up), config, others)


def test_the_crater_under_an_overhang_takes_the_colour_of_the_support_around_it_the_plane_keeps_its_own():
    from engine.edit.underside import paint

    floor, lit, seen, ball, sunk = crater_scene()
    found = crater_underside(floor, seen, ball, EffectsConfig())
    assert found is not None and np.array_equal(found.painted, sunk)
    assert np.all(found.colour >= lit.min(0) - 1e-6) and np.all(found.colour <= lit.max(0) + 1e-6)
    after = colors_of(paint(gaussians(floor, seen), found))
    assert np.allclose(after[sunk], found.colour, atol=1e-5)
    assert np.allclose(after[~sunk], seen[~sunk], atol=1e-5)  # on the plane, striped under the ball as before
    assert found.weight.min() == 1.0  # far darker than the support around: the effect masks take it


def test_the_crater_takes_the_mean_colour_of_a_support_of_uneven_stripes_not_its_majority_colour():
    floor, _, seen, ball, sunk = crater_scene()
    pale = (floor[:, 0] / 0.1) % 1 < 0.7  # 70% pale stripes, 30% dark, as wood's can be
    seen = np.where(sunk[:, None], seen, np.where(pale[:, None], [0.8, 0.65, 0.45], [0.55, 0.3, 0.3]))
    # about the ring underside.RING takes (1-1.5 footprint radii); any band this wide holds the stripes at 70/30
    ring = (np.linalg.norm(floor[:, :2], axis=1) > 0.4) & (np.linalg.norm(floor[:, :2], axis=1) < 0.6)
    found = crater_underside(floor, seen, ball, EffectsConfig())
    # a flat fill scores best at the texture's mean; the median is the pale stripes' colour (G +0.1 too bright)
    assert found is not None and np.allclose(found.colour, seen[ring].mean(0), atol=0.02)


def test_a_patch_of_the_support_is_laid_where_none_was_built_under_the_object_and_nowhere_else():
    """The floor under one half of the box was never built (the views saw the box there), and a table of another
    colour lies 0.1 below: after removal every view would look through to it (a toy on a cloth: the table's wood
    showed where the toy stood). A flat patch in the floor's colour around covers that half, on the floor's plane;
    the half that was built gets none, and a floor built everywhere none at all."""
    from engine.edit.underside import _cover, find_unbuilt

    floor, lit, seen, truth, box = shadow_scene(sun(30), darken=1.0)
    bare = (np.abs(floor[:, 0]) < 0.15) & (np.abs(floor[:, 1]) < 0.15) & (floor[:, 0] < 0)
    table = floor[np.linalg.norm(floor[:, :2], axis=1) < 0.5] - [0.0, 0.0, 0.1]
    built = gaussians(np.concatenate([floor[~bare], table]),
                      np.concatenate([seen[~bare], np.tile([0.5, 0.3, 0.1], (len(table), 1))]))
    up = np.array([0.0, 0.0, 1.0])
    core = object_core(gaussians(box, np.full((len(box), 3), 0.9)), up)
    plane = object_support(floor, core, up)
    patch = find_unbuilt(built, core, plane, EffectsConfig())
    assert patch is not None
    assert np.abs(patch["means"][:, 2].numpy()).max() < 1e-3  # on the floor's plane, not the table's
    assert patch["means"][:, 0].max() < 0.05  # over the bare half only, within a cell of its edge
    assert np.all(np.abs(colors_of(patch) - lit.mean(0)) < 0.1)  # the floor's colour around
    laid = {k: torch.cat([built[k], patch[k]]) for k in built}
    everything = np.ones(len(laid["means"]), bool)
    cover = _cover(laid, everything & (laid["means"][:, 2].numpy() > -0.05), lambda p: p[:, :2], floor[bare, :2],
                   0.01)
    assert cover.min() >= EffectsConfig().unbuilt_cover
    assert find_unbuilt(gaussians(floor, seen), core, plane, EffectsConfig()) is None


def test_the_support_left_part_transparent_under_the_object_gets_a_patch_only_above_the_configured_cover():
    """Under one half of the box the floor was built faint (the views saw the box there, and trained its edge thin):
    it covers the floor part way, so a render shows it darkened over black, the rim past a removed object's
    hole. At `unbuilt_cover` 0.5 (only where never built) nothing is laid there; at the default 0.9 (`remove
    --unbuilt-cover`) the patch is laid over that half only, and the floor then covers it past 0.9."""
    from engine.edit.underside import _cover, find_unbuilt

    floor, lit, seen, truth, box = shadow_scene(sun(30), darken=1.0)
    faint = (floor[:, 0] < 0) & (floor[:, 0] > -0.4) & (np.abs(floor[:, 1]) < 0.4)  # past the box's half, too
    under = faint & (np.abs(floor[:, 0]) < 0.15) & (np.abs(floor[:, 1]) < 0.15)
    built = gaussians(floor, seen)
    built["opacities"][torch.as_tensor(faint)] = math.log(0.15 / 0.85)
    up = np.array([0.0, 0.0, 1.0])
    core = object_core(gaussians(box, np.full((len(box), 3), 0.9)), up)
    plane = object_support(floor, core, up)
    before = _cover(built, np.ones(len(floor), bool), lambda p: p[:, :2], floor[under, :2], 0.01)
    assert before.min() > 0.5 and np.median(before) < 0.9  # part way: neither never built nor whole
    assert find_unbuilt(built, core, plane, EffectsConfig(unbuilt_cover=0.5)) is None
    assert EffectsConfig().unbuilt_cover == 0.9
    patch = find_unbuilt(built, core, plane, EffectsConfig())
    assert patch is not None and patch["means"][:, 0].max() < 0.05  # over the faint half only
    laid = {k: torch.cat([built[k], patch[k]]) for k in built}
    cover = _cover(laid, np.ones(len(laid["means"]), bool), lambda p: p[:, :2], floor[under, :2], 0.01)
    assert np.median(cover) >= 0.9


def looking_down_at_origin(position: np.ndarray, size: int = 96) -> Camera:
    """A camera at `position` looking at the origin, +z up: its rows are right, down and forward."""
    forward = -position / np.linalg.norm(position)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    rotation = np.stack([right, np.cross(forward, right), forward])
    return Camera(name="v.png", width=size, height=size, fx=size, fy=size, cx=size / 2, cy=size / 2, R=rotation,
                  t=-rotation @ position)


def depth_through(camera: Camera, through: np.ndarray) -> np.ndarray:
    """(H, W) z-depth of shadow_scene's floor (z = 0) seen by `camera`, except where the ray meets it inside the box
    `through` (x0, x1, y0, y1): there it goes on to the room's floor at z = -0.5, as a view sees through a support
    built with gaps."""
    u, v = pixel_grid(camera)
    rays = np.stack([(u - camera.cx) / camera.fx, (v - camera.cy) / camera.fy, np.ones_like(u)], -1) @ camera.R
    centre = -camera.R.T @ camera.t
    hit = centre + rays * (-centre[2] / rays[..., 2])[..., None]  # z-depth 1 a ray step: the step is the depth
    inside = ((hit[..., 0] > through[0]) & (hit[..., 0] < through[1]) & (hit[..., 1] > through[2])
              & (hit[..., 1] < through[3]))
    return np.where(inside, (-0.5 - centre[2]) / rays[..., 2], -centre[2] / rays[..., 2])


def test_a_support_the_views_see_through_gets_a_patch_though_its_cover_from_above_is_whole():
    """The floor is built everywhere (its cover from above is whole), but under one half of the box the views see
    through it to a floor 0.5 below (a table's top built of large Gaussians with gaps between them from the side: a
    dark disc where a ball stood). Given the training views' depth (`remove --patch-seen-through`, the default) a
    patch is laid over that half only; from the Gaussians alone, none."""
    from engine.edit.underside import find_unbuilt

    floor, lit, seen, truth, box = shadow_scene(sun(30), darken=1.0)
    built = gaussians(floor, seen)
    up = np.array([0.0, 0.0, 1.0])
    core = object_core(gaussians(box, np.full((len(box), 3), 0.9)), up)
    plane = object_support(floor, core, up)
    cameras = [looking_down_at_origin(np.array([2.0 * np.cos(a), 2.0 * np.sin(a), 1.5]))
               for a in np.linspace(0.0, 2.0 * np.pi, 8, endpoint=False)]
    depths = [depth_through(camera, np.array([-0.15, 0.0, -0.15, 0.15])) for camera in cameras]
    assert find_unbuilt(built, core, plane, EffectsConfig()) is None
    patch = find_unbuilt(built, core, plane, EffectsConfig(), views=(cameras, depths))
    assert patch is not None
    assert np.abs(patch["means"][:, 2].numpy()).max() < 1e-3  # on the floor's plane
    assert patch["means"][:, 0].max() < 0.05  # over the half seen through, within a cell of its edge
    assert EffectsConfig().patch_seen_through  # `remove` gives it the views unless told --no-patch-seen-through


def test_given_the_views_the_patch_takes_the_colour_they_show_round_the_object_not_that_of_gaussians_none_sees():
    """Under the floor's surface lies a second layer of Gaussians no view sees (training left them grey), as a
    trained support holds: the mean of the Gaussians' base colours in the ring is half grey, a patch of it shows
    paler or darker than the floor round it. Given the views' samples (`remove --seen-colour`), the patch takes
    what they show of the ring."""
    from engine.edit.underside import find_unbuilt

    floor, lit, seen, truth, box = shadow_scene(sun(30), darken=1.0)
    bare = (np.abs(floor[:, 0]) < 0.15) & (np.abs(floor[:, 1]) < 0.15) & (floor[:, 0] < 0)
    under = floor[~bare] - [0.0, 0.0, 0.01]
    built = gaussians(np.concatenate([floor[~bare], under]),
                      np.concatenate([seen[~bare], np.full((len(under), 3), 0.3)]))
    up = np.array([0.0, 0.0, 1.0])
    core = object_core(gaussians(box, np.full((len(box), 3), 0.9)), up)
    plane = object_support(floor, core, up)
    r = np.linalg.norm(floor[:, :2], axis=1)
    ring_truth = seen[(r > 0.25) & (r < 0.3)].mean(0)  # about underside.RING's ring past the box's footprint
    given = find_unbuilt(built, core, plane, EffectsConfig(), shown=view_samples(floor, seen))
    assert given is not None and np.all(np.abs(colors_of(given)[0] - ring_truth) < 0.05)
    by_gaussians = find_unbuilt(built, core, plane, EffectsConfig())
    assert np.abs(colors_of(by_gaussians)[0] - ring_truth).max() > 0.1  # the hidden grey layer in the mean
    assert EffectsConfig().seen_colour  # and `remove` gives it the views' samples unless told --no-seen-colour


def test_other_objects_bases_keep_their_own_colours_in_the_contact_shade_and_the_crater():
    """Another object stands in the darkened ring beside the ball, its base dark (its own colour and contact
    shadow), and part of the sunk crater under the ball belongs to it by identity: neither is brightened or
    repainted as the removed object's effect, while the support around them is."""
    from engine.edit.contact_shade import find_contact_shade

    floor, lit, seen, ball = overhang_scene(darken=0.2)
    r = np.linalg.norm(floor[:, :2], axis=1)
    base = (np.abs(floor[:, 0] - 0.5) < 0.05) & (np.abs(floor[:, 1]) < 0.05)  # in the zone, 0.45-0.55 out
    seen = np.where(base[:, None], 0.1, seen)
    up = np.array([0.0, 0.0, 1.0])
    core = object_core(gaussians(ball, np.full((len(ball), 3), 0.9)), up)
    plane = object_support(floor, core, up)
    shade = find_contact_shade(gaussians(floor, seen), core, plane, Samples(floor, seen), EffectsConfig(), others=base)
    assert shade is not None and not shade.shaded[base].any()
    assert shade.shaded[(r < 0.6) & ~base].mean() > 0.9  # the support beside it is relit as before

    floor, lit, seen, ball, sunk = crater_scene()
    theirs = sunk & (floor[:, 1] > 0)
    found = crater_underside(floor, seen, ball, EffectsConfig(), others=theirs)
    assert found is not None and np.array_equal(found.painted, sunk & ~theirs)


def test_nothing_is_repainted_where_the_support_under_the_object_lies_on_its_plane_or_when_switched_off():
    floor, lit, _, ball = overhang_scene(darken=1.0)
    assert crater_underside(floor, lit, ball, EffectsConfig()) is None
    floor, _, seen, ball, _ = crater_scene()
    assert crater_underside(floor, seen, ball, EffectsConfig(underside_reach=0.0)) is None


@pytest.mark.slow
def test_removal_writes_the_effects_folder_for_every_view(tiny_run, tmp_path):
    from engine.edit.removal import RemovalConfig, run_removal
    from engine.formats.layout import RemovedLayout
    from engine.io.image_io import read_png
    from engine.train.trained_run import load_run

    out = tmp_path / "removed"
    report = run_removal(RemovalConfig(run=str(tiny_run), object="plush", out=str(out), device="cpu"))
    effects = RemovedLayout(out).effects
    saved = json.loads(effects.report.read_text())
    assert set(saved) >= {"shadow", "search", "contact", "recall", "precision", "views_scored"}
    assert (saved["search"]["verdict"] == "found") == (saved["shadow"] is not None)
    assert saved["shadow"] is not None  # the plush's shadow on the table
    # relit in rounds until its dark samples brightened by the gain: one round left them LACKING short
    assert max(saved["shadow"]["lacking"]) < 1.05 <= max(saved["shadow"]["residual_gain"]), saved["shadow"]
    # the darkening under the plush looked for again after each relight (found again here: the crater's grazing
    # Gaussians draw it dark), and brightened in all by at most the one relight's bound (without it: 242x)
    contact = saved["contact"]
    assert contact is not None and len(contact["contrast_after_relights"]) >= 1, contact
    assert max(contact["max_gain"]) <= EffectsConfig().contact_most ** 2.4 + 1e-3, contact
    assert report["support_plane"] is not None and json.loads((out / "removal.json").read_text())["support_plane"]
    scene = load_run(tiny_run).scene
    for camera in scene.cameras:
        assert read_png(effects.mask(camera.name), "mask", camera.size).shape == (camera.height, camera.width)
    assert effects.sheet.is_file()
    if saved["shadow"] or saved["contact"]:  # what was found is scored against the generator's effects/
        assert saved["views_scored"] == len([i for i, truth in scene.effects.items() if truth.any()])


@pytest.mark.slow
def test_a_tiny_statue_run_finds_its_shadow_and_its_holes(statue_scene, tmp_path):
    """The targets for what CI can afford: on a statue scene, effect recall >= 0.6 and precision >= 0.5,
    hole IoU >= 0.6. Measured on this scene (8 views of 96x72, 800 CPU steps), training seeds 0 / 1 / 2: recall
    0.67 / 0.63 / 0.63, precision 0.96 / 0.94 / 0.91, hole IoU 0.68 / 0.64 / 0.65, over every view (the scene
    has gt/ for all). Before Gaussians centred below the support's band counted when their extent reaches into
    it, seed 1 recalled 0.41."""
    from engine.edit.holes import HoleConfig, run_holes
    from engine.edit.removal import RemovalConfig, run_removal
    from engine.train.config import TrainConfig
    from engine.train.run import train

    run = tmp_path / "run"
    train(TrainConfig(scene=str(statue_scene), out=str(run), preset="tiny", device="cpu", steps=800,
                      refine_start=50, refine_stop=150))
    effects = run_removal(RemovalConfig(run=str(run), object="statue", device="cpu"))["effects"]
    assert effects["shadow"] is not None and effects["views_scored"] >= 5, effects
    assert effects["recall"] >= 0.6 and effects["precision"] >= 0.5, effects
    holes = run_holes(HoleConfig(run=str(run)))
    assert holes["mean_unseen_iou_vs_truth"] >= 0.6, holes


def test_residual_gain_is_what_the_relit_shadow_still_lacks():
    """Measured again after relighting, on the shadow's own dark samples: brightened by 1.2 for a gain of 1.5,
    they ask for 1.25 more; brightened all the way (or past it) they ask for nothing, never for darkening. The lit
    samples beside the shadow do not count: they lie elsewhere, on other texture (they made it overshoot). Gains are
    of light, so the samples are brightened in linear values and shown in sRGB ones, as the renders are."""
    from engine.edit.effects import Samples, Shadow, residual_gain

    rng = np.random.default_rng(0)
    colors = rng.uniform(0.2, 0.4, (100, 3))
    dark, lit = np.r_[np.ones(50, bool), np.zeros(50, bool)], np.r_[np.zeros(50, bool), np.ones(50, bool)]
    shadow = Shadow(shadowed=np.ones(4, bool), darkness=np.ones(4), gain=np.full(3, 1.5), elevation=45.0,
                    azimuth=0.0, contrast=0.4, pick=np.arange(100), dark=dark, lit=lit)
    before = Samples(points=np.zeros((100, 3)), colors=colors)

    def after(dark_by: float, lit_by: float) -> Samples:
        light = srgb_to_linear(colors) * np.where(dark, dark_by, lit_by)[:, None]
        return Samples(points=np.zeros((100, 3)), colors=linear_to_srgb(light))
    assert np.allclose(residual_gain(shadow, before, after(1.2, 1.0)), 1.25, atol=0.01)
    assert np.allclose(residual_gain(shadow, before, after(1.2, 3.0)), 1.25, atol=0.01)  # the lit ones: no say
    assert np.allclose(residual_gain(shadow, before, after(1.5, 1.0)), 1.0, atol=0.01)
    assert np.allclose(residual_gain(shadow, before, after(1.8, 1.0)), 1.0)  # over-bright: left, not darkened


def test_the_relight_rounds_stop_at_the_gain_where_relighting_does_not_reach_the_dark_samples(tiny_run):
    """A shadow whose Gaussians hold none of its dark samples (a wrong light's cast): every round finds them as
    dark as before and asks for the whole gain again; in all the rounds relight by at most the gain once more,
    not by the gain to the power of the rounds."""
    from engine.edit.effects import Shadow
    from engine.edit.removal import RESIDUAL_ROUNDS, _relit_to_gain, _train_samples
    from engine.render.render_views import render_pictures
    from engine.train.trained_run import load_run

    run = load_run(tiny_run)
    after = list(render_pictures(run.gaussians, run.scene.cameras, run.sh_degree, "cpu"))
    regions = [np.zeros((c.height, c.width), bool) for c in run.scene.cameras]
    before = _train_samples(run.scene, after, regions)
    means = run.gaussians["means"].numpy()
    shadowed = np.zeros(len(means), bool)
    shadowed[np.argsort(means[:, 0])[:40]] = True  # at one end of the scene
    far = np.linalg.norm(before.points[:, None] - means[shadowed][None], axis=-1).min(1)
    pick = np.argsort(far)[-400:]  # the samples farthest from them are "dark"
    shadow = Shadow(shadowed=shadowed, darkness=np.ones(40), gain=np.full(3, 2.0), elevation=45.0, azimuth=0.0,
                    contrast=0.4, pick=pick, dark=np.ones(400, bool), lit=np.zeros(400, bool))
    _relit_to_gain(run, run.gaussians, shadow, before, after, regions, "cpu")
    assert RESIDUAL_ROUNDS > 1 and np.all(shadow.residual <= 2.0 + 1e-6), shadow.residual
    assert np.all(shadow.lacking > 1.9)  # they lack it still: no relight reaches them


def plaque_scene(light: np.ndarray, darken: float = 0.2):
    """A wall (z = 0) of nearly even Gaussians with a plaque on it (0.6 x 0.7, 0.05 thick) holding a thin peg, the
    wall in their shadow under `light` darkened by `darken` (linear): a trophy's mount, whose own shadow is a strip
    along two of its edges. Returns the wall's Gaussians left (none under the plaque) with their lit and seen
    colours, which of them are in shadow, the object's points and the views' samples (none under the plaque)."""
    xs = np.arange(-1.5, 1.5, SPACING)
    wall = np.stack(np.meshgrid(xs, xs, indexing="ij"), -1).reshape(-1, 2)
    wall = np.concatenate([wall, np.zeros((len(wall), 1))], 1)
    lit = np.where((np.floor(wall[:, 0] / 0.06) % 2 == 1)[:, None], [0.8, 0.78, 0.7], [0.78, 0.77, 0.69])
    parts = [(-0.3, 0.3, -0.35, 0.35, 0.0, 0.05), (-0.02, 0.02, -0.07, 0.17, 0.05, 0.1)]
    ray = wall[:, None, :] + np.linspace(0.001, 0.6 / light[2], 300)[None, :, None] * light
    shadowed, points = np.zeros(len(wall), bool), []
    for x0, x1, y0, y1, z0, z1 in parts:
        shadowed |= ((ray[..., 0] > x0) & (ray[..., 0] < x1) & (ray[..., 1] > y0) & (ray[..., 1] < y1)
                     & (ray[..., 2] > z0) & (ray[..., 2] < z1)).any(1)
        points.append(np.stack(np.meshgrid(np.arange(x0 + 0.01, x1, SPACING), np.arange(y0 + 0.01, y1, SPACING),
                                           np.arange(z0 + 0.01, z1, SPACING / 2), indexing="ij"), -1).reshape(-1, 3))
    under = (np.abs(wall[:, 0]) < 0.3) & (np.abs(wall[:, 1]) < 0.35)
    seen = np.where((shadowed & ~under)[:, None], linear_to_srgb(srgb_to_linear(lit) * darken), lit)
    samples = view_samples(wall, seen, hidden=under)
    outside = ~((np.abs(samples.points[:, 0]) < 0.3) & (np.abs(samples.points[:, 1]) < 0.35))
    samples = Samples(points=samples.points[outside], colors=samples.colors[outside])
    return wall[~under], lit[~under], seen[~under], shadowed[~under], np.concatenate(points), samples


def test_a_flat_mounts_shadow_strip_is_its_own_not_darkness_around_it():
    """A light 90+ degrees from the found one that is about as dark says the darkness surrounds the object (a
    tree's band: test above). A flat mount's cast from such a light is a strip along its edge that runs into
    the mount's own shadow there; counted, the strip made the wall family's shadow 'surrounding' and it stayed
    on the wall (a CPU wallmount of seed 90: 0.43 elsewhere against 0.50 found, removal 22.2 dB outside the
    true hole; 27.3 with the strip's own-shadow samples left out). Here: 0.74 elsewhere against 0.76 counted."""
    wall, lit, seen, truth, plaque, samples = plaque_scene(sun(45))
    search = search_of(gaussians(wall, seen), gaussians(plaque, np.full((len(plaque), 3), 0.9)), samples)
    assert search.verdict == "found", search.report()
    assert search.report()["darkest_elsewhere"] < 0.2
    shadow = search.shadow
    assert (shadow.shadowed & truth).sum() > 0.7 * truth.sum(), shadow.report()
