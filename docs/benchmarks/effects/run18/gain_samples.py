"""Issue 16's green relit shadow (docs/BENCHMARKS.md, "Run 7"): on the GPU livingroom the cast shadow's gain came
out R 1.595, G 1.627, B 1.434, where the exact images give gt / input 1.62 / 1.58 / 1.47 in the deep shadow. The
suspect: find_shadow takes as dark the samples of the candidate shadow that are darker than the lit median by
min_contrast, which takes the wood's dark stripes (G 101 of 255) more readily than its light ones (G 156), and G
is the channel the stripes differ most in. This computes the gain three ways from one search on the 640 scene's
exact data (run16/emulate_gain.py's set-up: the views' samples lifted with the generator's depth):
- luminance: `find_shadow`'s own (median of the lit edge over median of the dark samples);
- geometry: the dark samples are all the candidate shadow's samples at least one grid cell inside the object's
  cast footprint, whatever their luminance;
- means: the ratio of the two sets' mean colours, dark samples as find_shadow picks them.
On a trained run the same variants need a GPU (`remove` renders every view twice); the exact data only shows
whether a variant keeps the truth's channel order.

    PYTHONPATH=. python docs/benchmarks/effects/run18/gain_samples.py .bench/640/livingroom_s0
"""

import sys
from pathlib import Path

import cv2
import numpy as np

from engine.edit.plane_grid import Site

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "run16"))
from emulate_gain import exact_search  # noqa: E402

found = exact_search(sys.argv[1])
scene, samples, obj, plane, shadow = found.scene, found.samples, found.obj, found.plane, found.search.shadow
truth = [(scene.gt_images[i][e].astype(float) + 1) / (scene.images[i][e].astype(float) + 1)
         for i in scene.test if i in scene.gt_images and i in scene.effects for e in [scene.effects[i]] if e.any()]
print("truth, gt / input in effects/, 50th and 75th percentile:",
      np.percentile(np.concatenate(truth), [50, 75], axis=0).round(3).tolist())
site = Site.of(obj, plane)
frame, grid = site.frame, site.grid
light = frame.light(shadow.elevation, shadow.azimuth)
points, colors = samples.points[shadow.pick], samples.colors[shadow.pick]
inside = grid.shadowed(frame, light, obj, points, site.spacing)
deep_cells = cv2.erode(grid.raster(frame.cast(obj, light), site.spacing).astype(np.uint8), np.ones((3, 3), np.uint8))
deep = inside & grid.cells(deep_cells > 0, frame.cast(points, light))
lit = colors[shadow.lit]
for name, dark, average in (("luminance (find_shadow)", shadow.dark, np.median), ("geometry", deep, np.median),
                            ("means", shadow.dark, np.mean), ("geometry, means", deep, np.mean)):
    gain = (average(lit, 0) + 1e-3) / (average(colors[dark], 0) + 1e-3)
    share = (colors[dark] @ np.array([0.2126, 0.7152, 0.0722]) < np.median(lit @ np.array([0.2126, 0.7152, 0.0722])))
    print(f"{name:24s} dark samples {int(dark.sum()):6d}  gain {gain.round(3).tolist()}  "
          f"G/R {gain[1] / gain[0]:.3f}  (below the lit median luminance: {share.mean():.2f})")
