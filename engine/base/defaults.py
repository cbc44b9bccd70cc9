"""What `complete` and `inpaint` do by default, chosen by the held-out table (docs/BENCHMARKS.md, "Held-out table"):
the method and inpainter with the best mean m-PSNR among those below the unfilled hole on no held-out scene. A
module of its own at the bottom layer, free of torch and numpy, because the CLI, both stages and the Blender
add-on's menus read it.

None qualified at 33d96f8 (every cell finished is below the unfilled hole on livingroom_s100, livingroom_s101
and statue_s100), nor at 6f87d43 with the masks grown before inpainting (Ref-telea +3.27, +11.05 and +3.85 dB over
the unfilled hole on livingroom_s100, tabletop_s100 and wallmount_s100, -7.52 on statue_s100), nor at 5e5ff92 on
the eight tuning scenes `_s8`/`_s90` (Ref-telea above it on seven, mean +5.36 dB, -1.15 on statue_s90), so `complete`
without --method leaves the hole as removal left it and says so; BEST_ON_MEAN (Ref-telea) is the fill it names for
those who fill the hole anyway, and its inpainter is what `inpaint` takes by default.
"""

DEFAULT_METHOD = ""  # "": leave the hole
BEST_ON_MEAN = ("reference", "telea")  # (method, inpainter)
DEFAULT_INPAINTER = BEST_ON_MEAN[1]
VERDICT = ("no completion method scored above the unfilled hole on every held-out scene (docs/BENCHMARKS.md, "
           "\"Held-out table\"), so by default the hole stays as removal left it")
