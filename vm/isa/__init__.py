"""The DCD-VM instruction set: table, assembler, disassembler, verifier."""
