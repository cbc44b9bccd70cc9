"""Stage 4, 2D inpainting: the inpainter interface and registry (registry.py), one file per inpainter
(inpainters/), depth as a grey image, and the stage over a run's views (run.py). May import edit and below."""
