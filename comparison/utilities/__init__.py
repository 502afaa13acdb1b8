"""The suite's utilities, which know nothing of walls: numbers, names, outputs, progress, inputs.

* :mod:`~comparison.utilities.numbers`: numbers written as text, one rule, read exactly;
* :mod:`~comparison.utilities.names`: names a user gives (a user model's column, a wall of a walls file);
* :mod:`~comparison.utilities.outputs`: every file written whole or not at all;
* :mod:`~comparison.utilities.progress`: the progress display;
* :mod:`~comparison.utilities.inputs`: the files the suite reads (scenes, grids, walls files): regular files only;
* :mod:`~comparison.utilities.toml_source`: an error about a TOML input worded with the line of its key.

What a comparison is about (the wall, the verdict, ...) is in :mod:`comparison.domain`.
"""
