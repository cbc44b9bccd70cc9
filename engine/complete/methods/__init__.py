"""The completion methods, one file each (engine.complete.registry says what a file declares). Every
module here is imported when the registry is first asked, so adding a method is adding a file."""
