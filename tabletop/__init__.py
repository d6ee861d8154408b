"""Tabletop: the runtime that wires tracked pucks, engines and the projector view together."""

__version__ = "0.1.0"
