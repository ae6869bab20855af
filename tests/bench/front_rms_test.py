"""bench/front_rms.py against fronts built from the reference table itself: frames midway between the
table's points, on its linear interpolation, give 0 %; a front 10 % further along gives 10 %; --min-T,
--max-T, --back and the time scale select the frames."""
import importlib.util
import math
import os
import sys
import tempfile
import unittest

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
spec = importlib.util.spec_from_file_location("front_rms", os.path.join(ROOT, "bench", "front_rms.py"))
front_rms = importlib.util.module_from_spec(spec)
spec.loader.exec_module(front_rms)

G = 9.81


def write_front(points, a, n2, back, scale=1.0):
    """Frames at the table's T, front x = back + a Z scale (the inverse of the script's mapping)."""
    f = tempfile.NamedTemporaryFile("w", suffix=".front", delete=False)
    for k, (T, Z) in enumerate(points, 1):
        t = T / (math.sqrt(n2) * math.sqrt(G / a))
        f.write(f"{k} {t!r} {back + a * Z * scale!r}\n")
    f.close()
    return f.name


class FrontRms(unittest.TestCase):
    def rms(self, errors):
        return 100 * math.sqrt(sum(e * e for e in errors) / len(errors))

    def check(self, table_name, a, n2, back):
        table = front_rms.read_reference(os.path.join(ROOT, "studies", "reference", table_name))
        mid = [((t0 + t1) / 2, (z0 + z1) / 2) for (t0, z0), (t1, z1) in zip(table, table[1:])]
        exact = write_front(mid, a, n2, back)
        ahead = write_front(mid, a, n2, back, 1.1)
        self.assertAlmostEqual(self.rms(front_rms.relative_errors(exact, table, a, n2, back, math.inf)), 0, 4)
        errors = front_rms.relative_errors(ahead, table, a, n2, back, math.inf)
        self.assertEqual(len(errors), len(mid))
        self.assertAlmostEqual(self.rms(errors), 10.0, 4)
        last = mid[len(mid) // 2][0]
        limited = front_rms.relative_errors(ahead, table, a, n2, back, last)
        self.assertEqual(len(limited), len(mid) // 2 + 1)
        late = front_rms.relative_errors(ahead, table, a, n2, back, math.inf, min_T=last)
        self.assertEqual(len(late), len(mid) - len(mid) // 2)

    def test_square_column(self):
        self.check("dam_break_martin_moyce_n1.csv", 1.0, 1.0, -1.95)

    def test_tall_column(self):
        self.check("dam_break_martin_moyce_n2.csv", 0.2, 2.0, 0.0)

    def test_long_tank(self):
        self.check("dam_break_martin_moyce_n2_long.csv", 0.05715, 2.0, 0.0)


if __name__ == "__main__":
    unittest.main()
