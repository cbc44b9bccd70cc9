"""Stage 1b, objects without masks (`segment`): a trained run's Gaussians grouped into objects from its
geometry and salient-object votes (`--auto`), from a 2D tool's masks, or from a click, a box or a selection.
What it writes is read back by engine.train.segment_objects. May import convert, train and everything below."""
