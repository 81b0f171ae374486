"""Figures: a sweep's (sweep, plot_sweep.py), a metrics folder's (metrics, plot_metrics.py), and the drawing they
and summarize_run.py share (drawing)."""
