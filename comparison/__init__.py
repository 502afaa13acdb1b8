"""Macro against micro: shared wall specs, the paper's cases, reports and the ``xcheck`` CLI."""
