"""bench/lattice_sums.py against analytic facts: each kernel integrates to 1 (its sum over a lattice much
finer than its support, here support 20 spacings, is 1 on every lattice); each lattice has one site per
spacing^3; the nearest-neighbour distances are 1, sqrt(3) / 2 cbrt(2) and cbrt(4) / sqrt(2) spacings."""
import importlib.util
import math
import os
import unittest

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
spec = importlib.util.spec_from_file_location("lattice_sums", os.path.join(ROOT, "bench", "lattice_sums.py"))
lattice_sums = importlib.util.module_from_spec(spec)
spec.loader.exec_module(lattice_sums)


class LatticeSums(unittest.TestCase):
    def test_every_kernel_integrates_to_one_on_every_lattice(self):
        for name, kernel in lattice_sums.KERNELS.items():
            for lattice in lattice_sums.LATTICES:
                with self.subTest(kernel=name, lattice=lattice):
                    self.assertAlmostEqual(lattice_sums.lattice_sum(kernel, lattice, 20.0), 1.0, delta=1e-4)

    def test_one_site_per_spacing_cubed(self):
        radius = 20.0
        for lattice in lattice_sums.LATTICES:
            with self.subTest(lattice=lattice):
                sites = len(lattice_sums.distances(lattice, radius))
                self.assertAlmostEqual(sites / (4 / 3 * math.pi * radius**3), 1.0, delta=0.01)

    def test_nearest_neighbour_distances(self):
        expected = {"sc": 1.0, "bcc": math.sqrt(3) / 2 * 2 ** (1 / 3), "fcc": 4 ** (1 / 3) / math.sqrt(2)}
        for lattice, d in expected.items():
            with self.subTest(lattice=lattice):
                self.assertAlmostEqual(sorted(lattice_sums.distances(lattice, 2.0))[1], d, places=9)


if __name__ == "__main__":
    unittest.main()
