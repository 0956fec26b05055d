"""Analysis on top of the core: periodic orbits and their stability, continuation, sweeps and regime maps."""
