"""Wiring of each registered kind: its config schema and its factory."""
