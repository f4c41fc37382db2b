"""``rdcd dap``: a Debug Adapter Protocol server that runs an RDCD program in the simulated worlds
of ``rdcd simulate`` and stops the whole world at breakpoints in the RDCD source."""
