"""Reactive behaviour by demonstration (Puppet Master)."""
