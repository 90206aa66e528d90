#!/usr/bin/env python3
"""The coefficients of `src/tracer/math/turn.rs`: sin(pi f) = f P(f^2), cos(pi f) = 1 + f^2 Q(f^2)
on f in [-1/2, 1/2], P and Q of degree 4, by the Remez exchange algorithm in f64.

    python3 benches/turn_fit.py

Minimises the relative error of sin (the weight 1/P) and the error of Q (cos's error is f^2
times it, at most a quarter of it). Prints each coefficient as f64 and rounded to f32 (the
Rust literals are those f32 values), and each fit's maximum error before that rounding.
Standard library only.
"""

import math
import struct

HIGH = 0.25  # y = f^2 runs over [0, 1/4]
DEGREE = 5  # coefficients per polynomial
GRID = [HIGH * i / 20000 for i in range(20001)]


def solve(rows, rhs):
    """Gaussian elimination with partial pivoting."""
    n = len(rhs)
    a = [row[:] + [rhs[i]] for i, row in enumerate(rows)]
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(a[r][c]))
        a[c], a[p] = a[p], a[c]
        for r in range(n):
            if r != c:
                m = a[r][c] / a[c][c]
                a[r] = [x - m * y for x, y in zip(a[r], a[c])]
    return [a[i][n] / a[i][i] for i in range(n)]


def remez(target, weight, n, rounds=8):
    """Coefficients c minimising max |weight(y) (target(y) - sum c_j y^j)| on [0, HIGH]."""
    nodes = [HIGH / 2 * (1 - math.cos(math.pi * k / n)) for k in range(n + 1)]
    for _ in range(rounds):
        rows = [[y**j for j in range(n)] + [(-1) ** k / weight(y)] for k, y in enumerate(nodes)]
        coefficients = solve(rows, [target(y) for y in nodes])[:n]

        def error(y):
            return weight(y) * (target(y) - sum(c * y**j for j, c in enumerate(coefficients)))

        # The next nodes: the error's alternating extremes (the ends and its turning points).
        turning = [b for a, b, c in zip(GRID, GRID[1:], GRID[2:]) if (error(b) - error(a)) * (error(c) - error(b)) <= 0]
        extremes = [GRID[0]] + turning + [GRID[-1]]
        if len(extremes) == n + 1:
            nodes = extremes
    return coefficients, max(abs(error(y)) for y in GRID)


def sin_over_f(y):
    f = math.sqrt(y)
    return math.sin(math.pi * f) / f if f else math.pi


def cos_minus_one_over_y(y):
    f = math.sqrt(y)
    return (math.cos(math.pi * f) - 1) / y if y else -(math.pi**2) / 2


def as_f32(x):
    return struct.unpack("f", struct.pack("f", x))[0]


def main():
    p, p_error = remez(sin_over_f, lambda y: 1 / sin_over_f(y), DEGREE)
    q, q_error = remez(cos_minus_one_over_y, lambda y: 1.0, DEGREE)
    print(f"P (sin, relative error {p_error:.2e}):")
    for c in p:
        print(f"  {c!r:>24}  f32 {as_f32(c)!r}")
    print(f"Q (cos, error of Q {q_error:.2e}, of cos at most a quarter of it):")
    for c in q:
        print(f"  {c!r:>24}  f32 {as_f32(c)!r}")


if __name__ == "__main__":
    main()
