"""Stage 5, completion: the completion-method registry (registry.py), one file per method (methods/),
the one loop that runs any of them and scores the result (run.py), FT's finetuning, COLMAP re-estimation,
and the catalogue of plug-ins for the CLI, Blender and the README. May import every stage below it."""
