"""The node graph: forage (foraging.launch and how its runs ended), the arguments a launch file declares
(launch_args), health (/diagnostics) and the parameter docs (param_docs)."""
