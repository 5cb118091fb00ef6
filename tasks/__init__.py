"""Methodology stages: one module per stage, each a registered peenflow task."""
