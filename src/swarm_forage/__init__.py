"""swarm_forage's Python side, one sub-package per concern:

experiment  experiment files: the build's controller kinds and models, a file loaded and checked, its runs
sweep       a sweep: its command (cli), one sweep's steps, records, estimate, rounds, jobs, SLURM, forks, reuse
study       the paper's study: paper, its report, claims and their verdicts, the bootstrap, intervals, the
            ablation, claim variants, the models table
recommend   the (controller, N) a target calls for, from a run library
robustness  the noise and population axes, their tables, figures and report section
figures     a sweep's figures and a metrics folder's, and the drawing they share
bags        a recorded run read (runs), summarized, compared; the reference bags
graph       the node graph: forage, launch arguments, health, the parameter docs

The generated message modules (swarm_forage.msg, swarm_forage.srv) live beside these in the devel space."""
