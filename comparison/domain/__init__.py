"""What a comparison is about: the wall, its scenes, the paper's cases, the verdict and its proof, local
mechanisms and failure modes.

* :mod:`~comparison.domain.wall`: :class:`~comparison.domain.wall.WallSpec`, one wall in the terms both
  models take, and its conversion to each;
* :mod:`~comparison.domain.scene`: a dimensional wall given storey by storey in a TOML scene;
* :mod:`~comparison.domain.cases`: the paper's cases and every value it publishes for them;
* :mod:`~comparison.domain.verdict`: :func:`~comparison.domain.verdict.compare`, both models on one wall and
  the verdict on the macro model;
* :mod:`~comparison.domain.proof`: what proves a verdict (a bound, a certified state, a closed search);
* :mod:`~comparison.domain.wall_mechanism`: the wall's own mechanism where a local one governs the block
  model;
* :mod:`~comparison.domain.failure`: failure modes, the micro mechanism read in the macro model's terms.

The suite's utilities (numbers, names, outputs, progress, inputs) are in :mod:`comparison.utilities`.
"""
