"""Studies built on the solver and its baselines: the replication claims, work-precision, the hard cases."""
