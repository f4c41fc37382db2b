"""Lattice geometry of ATRON structures and the physics-free lattice world."""
