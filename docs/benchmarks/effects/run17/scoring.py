"""The effects experiments' one score of a removed scene (run16/overshoot.py, run17/variants.py): its test views
against gt/, PSNR outside the true hole and in the true effect pixels (mean over the views, as removal.json's
psnr_outside_hole), and the effect pixels' removed / gt/ ratio per channel (25th, 50th, 75th percentile)."""

import numpy as np

from engine.edit import removal


def score(run, gaussians, name: str, device) -> None:
    scene = run.scene
    tests = [i for i in scene.test if i in scene.gt_images and i in scene.holes]
    pictures = list(removal.render_pictures(gaussians, [scene.cameras[i] for i in tests], run.sh_degree, device,
                                            depth=False))
    outside, effect, ratios = [], [], []
    for i, picture in zip(tests, pictures, strict=True):
        rgb, gt = picture.rgb.astype(float), scene.gt_images[i].astype(float)
        hole = scene.holes[i]
        outside.append(((rgb - gt)[~hole] ** 2).mean())
        if i in scene.effects and scene.effects[i].any():
            e = scene.effects[i] & ~hole
            effect.append(((rgb - gt)[e] ** 2).mean())
            ratios.append((rgb[e] + 1) / (gt[e] + 1))

    def db(mse: list) -> float:
        return round(float(np.mean([10 * np.log10(255 ** 2 / max(m, 1e-9)) for m in mse])), 2) if mse else float("nan")
    pct = np.percentile(np.concatenate(ratios), [25, 50, 75], 0).round(3).tolist() if ratios else None
    print(f"{name:40s} outside the hole {db(outside)} dB, effect pixels {db(effect)} dB, removed/gt {pct}", flush=True)


def effects_stage(description: str):
    """The arguments RUN OBJECT [--device] and removal's effects stage up to the cast shadow's search, as `remove`
    runs it on a trained run, but searched without the other objects (the search of run 4, before their_shadows):
    a namespace of run, scene, device, remaining, core, plane, regions, others, after (the removed renders),
    config, before (their training samples) and search."""
    import argparse
    from types import SimpleNamespace

    from engine.base.device import pick_device
    from engine.edit.effects import EffectsConfig, find_shadow
    from engine.edit.support_plane import object_core, object_support
    from engine.formats.cameras import mean_up
    from engine.train.trained_run import load_run

    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("run")
    parser.add_argument("object")
    parser.add_argument("--device", default="auto")
    args = parser.parse_args()
    device = pick_device(args.device)
    run = load_run(args.run, None)
    scene = run.scene
    chosen, _ = removal.select(run, removal.RemovalConfig(run=args.run, object=args.object))
    remaining, gone = removal.keep(run.gaussians, chosen), removal.keep(run.gaussians, ~chosen)
    up = mean_up(np.stack([c.R for c in scene.cameras]))
    core = object_core(gone, up)
    plane = object_support(remaining["means"].numpy(), core, up)
    obj = scene.object_by(args.object)
    regions = [scene.masks[i] == obj.id for i in range(len(scene.cameras))]
    others = removal.other_objects(run, remaining, obj.id)
    after = list(removal.render_pictures(remaining, scene.cameras, run.sh_degree, device))
    config = EffectsConfig()
    before = removal._train_samples(scene, after, regions)
    search = find_shadow(remaining, core, plane, before, config)
    assert search.shadow is not None, search.verdict
    return SimpleNamespace(run=run, scene=scene, device=device, remaining=remaining, core=core, plane=plane,
                           regions=regions, others=others, after=after, config=config, before=before, search=search)
