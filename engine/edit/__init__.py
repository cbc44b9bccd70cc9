"""Stages 2 and 3, removal and hole masks: deleting an object's Gaussians by identity or a box, and the
depth-guided masks of what no view saw behind it (with the support plane). May import segment and everything below."""
