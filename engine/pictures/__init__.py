"""Pictures people look at: a scene's contact sheet, side-by-side comparisons, labels and overlays, and
the benchmark's chart as PNG. May import metrics and everything below it."""
