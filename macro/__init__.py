"""Macro-block model of Argiento, Maione & Casapulla (2018)."""
