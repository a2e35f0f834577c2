#!/usr/bin/python3
"""Generate the committed SciPy reference of the Sobol sequence viaduct draws
(tests/unit/study/test_sampling.cpp): the first 256 points of SciPy's unscrambled Sobol
sequence in 32 dimensions (Joe and Kuo's direction numbers, Gray-code order), as the integer
coordinate bits (coordinate x 2^32).

Run with Debian's python3-scipy:  /usr/bin/python3 scripts/generate/gen_sobol_reference.py
Writes tests/data/sobol_reference.csv. Regenerate only on purpose (golden files).
"""
import os

import numpy as np
import scipy
from scipy.stats import qmc

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tests", "data", "sobol_reference.csv")


def main():
    x = qmc.Sobol(d=32, scramble=False).random_base2(8)
    bits = np.rint(x * 2.0**32).astype(np.uint64)
    with open(OUT, "w") as f:
        f.write(f"# scipy {scipy.__version__} qmc.Sobol(d=32, scramble=False).random_base2(8) x 2^32\n")
        for row in bits:
            f.write(",".join(str(int(v)) for v in row) + "\n")


if __name__ == "__main__":
    main()
