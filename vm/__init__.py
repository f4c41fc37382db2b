"""The DCD-VM: instruction set, interpreter, module runtime, lattice geometry and worlds."""
