"""What `complete` and `inpaint` do by default: the method and inpainter with the best mean m-PSNR in the true hole
among those below the unfilled hole on no tuning scene (scene seeds 0-99, where every default is chosen:
engine.formats.protocol); the held-out table (seeds 100 and up) only reports how the choice holds
(docs/BENCHMARKS.md, "Held-out table"). A module of its own at the bottom layer, free of torch and numpy, because
the CLI, both stages and the Blender add-on's menus read it.

The fill is Ref-coherence (coherence transport, engine.inpaint.inpainters.coherence). On the tuning
scenes measured with both at e541ab4 on one H200 (statue_s21, a tree's band across the plinth; s55, none; wallmount_s8)
Ref-coherence scored 28.09 / 26.64 / 32.01 dB against Ref-telea's 26.40 / 26.31 / 33.65 (mean 28.91 against 28.79),
above the unfilled hole on all three (25.78 / 24.31 / 24.31); on the wall it lost 1.64 dB (a dark rim at the hole's
border carried down the wall's grain). The held-out table only reports: there Ref-telea fell below the unfilled
hole on statue_s100 (-3.57; its band broken by a pale patch) and Ref-coherence was above it on all four scenes (mean
+5.47 against Ref-telea's +4.43). Before, Ref-telea (709b800: above the unfilled hole on all eight `_s8`/`_s90`
tuning scenes, mean 26.72 against 20.29), and before that the hole stayed as removal left it. The eight tuning
scenes with both fills are the check still owed. `--method ''` still leaves the hole (LEFT).
"""

DEFAULT_METHOD = "reference"  # "": leave the hole
BEST_ON_MEAN = ("reference", "coherence")  # (method, inpainter)
DEFAULT_INPAINTER = BEST_ON_MEAN[1]
WHY = ("Ref-coherence scored above the unfilled hole on every tuning scene measured with it (statue_s21, s55, "
       "wallmount_s8 at e541ab4: mean m-PSNR 28.91 against Ref-telea's 28.79 and the unfilled 24.80; "
       "docs/BENCHMARKS.md, \"Held-out table\")")
LEFT = "--method '' leaves the hole as removal left it"
