"""The solver core: parameters, the linear flow, events, the model, Algorithm No. 1, simulation and the settled motion."""
