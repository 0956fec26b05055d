"""Output for the workflow: records (CSV, JSON, logs), LaTeX formatting and the figure style."""
