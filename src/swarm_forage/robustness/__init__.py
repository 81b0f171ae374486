"""Robustness beyond the paper: an experiment's noise and population axes (axes), a sweep's robustness tables
(tables), their figures (figures) and the report's section (report)."""
