"""Recorded runs: read (runs: a run's series through read_run, its messages, a sweep's tables), summarized
(summary, summarize_run.py), compared message by message (compare) and the reference bags (reference)."""
