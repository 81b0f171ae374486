"""Hamann's model of performance against swarm size, P(N) ~ a * N^b * e^(c N), fitted per (controller, arena,
condition) by weighted least squares on log P = log a + b log N + c N (each size weighted by its seeds).
Its optimum is N* = -b/c (a maximum when b > 0 and c < 0). docs/recommend.md, Fit."""
import math

import numpy as np


class Fit:
    def __init__(self, a, b, c, r2, sizes, runs):
        self.a, self.b, self.c, self.r2 = a, b, c, r2
        self.sizes, self.runs = sizes, runs  # the measured sizes fitted, and their seeds

    def __call__(self, n):
        return self.a * n ** self.b * math.exp(self.c * n)

    def optimum(self):
        """N* = -b/c when the model has a maximum (b > 0, c < 0), else None."""
        return -self.b / self.c if self.b > 0 and self.c < 0 else None

    def describe(self):
        star = self.optimum()
        return 'a = %.4g, b = %.4g, c = %.4g, R^2 = %.3f over N = %s; %s' % (
            self.a, self.b, self.c, self.r2, ','.join(map(str, self.sizes)),
            'N* = -b/c = %.0f' % star if star else 'no interior optimum (b <= 0 or c >= 0)')


def fit(points):
    """The Fit of [(N, P, seeds)] (N >= 1, P > 0 only; at least 3 sizes), else None."""
    pts = [(float(n), float(p), max(1.0, float(w))) for n, p, w in points if n >= 1 and p is not None and p > 0]
    if len({n for n, _, _ in pts}) < 3:
        return None
    n = np.array([p[0] for p in pts])
    y = np.log([p[1] for p in pts])
    w = np.array([p[2] for p in pts])
    scale = n.max()  # c is fitted on N / max N, then rescaled: a well-conditioned system
    X = np.column_stack([np.ones_like(n), np.log(n), n / scale])
    sw = np.sqrt(w)
    coef, *_ = np.linalg.lstsq(X * sw[:, None], y * sw, rcond=None)
    pred = X @ coef
    mean = np.sum(w * y) / np.sum(w)
    total = np.sum(w * (y - mean) ** 2)
    r2 = 1.0 - np.sum(w * (y - pred) ** 2) / total if total > 0 else 1.0
    return Fit(math.exp(coef[0]), float(coef[1]), float(coef[2]) / scale, float(r2),
               sorted(int(p[0]) for p in pts), [int(p[2]) for p in sorted(pts)])


def scalability(p1, p2, n1, n2):
    """e(N1, N2) of final counts (docs/metrics.md, Scalability: phi = P(N2) / ((N2/N1) P(N1)), N2 in place
    of N1 when N1 = 1), None when undefined."""
    if not p1 or p1 <= 0 or p2 is None or p2 <= 0:
        return None
    phi = p2 / ((n2 / n1) * p1)
    used = n2 if n1 == 1 else n1
    return (1.0 / phi - 1.0 / used) / (1.0 - 1.0 / used)
