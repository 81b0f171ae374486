"""A sweep of an experiment file: its command (cli) and its steps (steps: plan, run, verify, tables), the records
and their lock (records), the estimate and progress (estimate), rounds of seeds (rounds), how runs are started
(jobs: GNU Parallel, SLURM arrays; slurm: checkpoints and resubmission), forks at alpha (forks) and records
linked from other folders (reuse)."""
