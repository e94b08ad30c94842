"""The 24 proper rotations of the cube built by hand, independent of scipy's groups."""

import itertools

import numpy as np


def cubic_group_by_hand() -> np.ndarray:
    """The 24 signed permutation matrices of determinant +1, shape (24, 3, 3)."""
    out = []
    for perm in itertools.permutations(range(3)):
        for signs in itertools.product((1, -1), repeat=3):
            S = np.zeros((3, 3))
            S[range(3), perm] = signs
            if np.linalg.det(S) > 0:
                out.append(S)
    return np.array(out)
