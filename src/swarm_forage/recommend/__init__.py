"""`recommend`: the (controller, N) a target calls for. Its command (cli), the target (target), the run library
(library), the fit of P(N) (model), the candidates and their score (rank), the text (report) and the figure
(figure)."""
