"""The 2D inpainters, one file each (engine.inpaint.registry says what a file declares). Every module here
is imported when the registry is first asked, so adding an inpainter is adding a file."""
