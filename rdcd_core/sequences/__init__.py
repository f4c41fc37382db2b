"""Reconfiguration sequences (docs/reconfiguration.md): the names check, the run through the lattice
model from a starting configuration, and the structure after each step (hover)."""
