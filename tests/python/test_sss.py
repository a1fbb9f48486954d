"""The Python package against the C decoder and the tools (docs/python.md).

Run by ctest with SSS_LIBRARY (the shared libsss), SSS_BAKE, SSS_STAT,
SSS_GENMESH and SSS_SOURCE set; argv[1] is a scratch directory. Every check
compares with something computed elsewhere: sss-stat's JSON (the C decoder
and reconstruction behind the command line), or another call path.
"""
import os
import shutil
import subprocess
import sys
import unittest

import numpy as np

sys.path.insert(0, os.path.join(os.environ["SSS_SOURCE"], "common", "python"))
import sss  # noqa: E402

TMP = sys.argv.pop(1)
GOLDEN = os.path.join(os.environ["SSS_SOURCE"], "tests", "data", "golden_v1.sss")
LIGHTS = [(0, 0, 1), (0.3, -0.5, 0.81), (-1, 0.2, -0.4), (0.1, 0.99, 0.05)]


def run(*cmd):
    r = subprocess.run([str(c) for c in cmd], capture_output=True, text=True)
    if r.returncode != 0:
        raise AssertionError(f"{cmd}: {r.stderr}")
    return r.stdout


def stat_q(path, v, light):
    """q at vertex v as sss-stat --query reconstructs it (float32)."""
    j = sss.stat(path, "--query", v, "--light", ",".join(map(str, light)))
    return np.array(j["reconstructed"], dtype=np.float32)


class Files:
    made = False

    @classmethod
    def make(cls):
        """A generated blob baked at the defaults (references, run-time near
        terms) and as float rows; made once."""
        if cls.made:
            return
        shutil.rmtree(TMP, ignore_errors=True)
        os.makedirs(TMP)
        cls.mesh = os.path.join(TMP, "blob.ply")
        run(os.environ["SSS_GENMESH"], "blob", 3, cls.mesh)
        cls.default = os.path.join(TMP, "default.sss")
        cls.float = os.path.join(TMP, "float.sss")
        common = ["--material", "skin1", "--mm-per-unit", 20, "--dirs", 50, "-q"]
        run(os.environ["SSS_BAKE"], cls.mesh, "-o", cls.default, *common)
        run(os.environ["SSS_BAKE"], cls.mesh, "-o", cls.float, *common, "--quant", "float")
        cls.made = True


class Golden(unittest.TestCase):
    def test_reads_the_golden_file(self):
        j = sss.stat(GOLDEN)
        with sss.open(GOLDEN) as a:
            i = a.info
            self.assertEqual((i["nv"], i["nf"], i["channels"], i["ndirs"]),
                             (j["vertices"], j["triangles"], j["channels"], j["directions"]))
            self.assertEqual(i["quant_name"], j["quant"])
            self.assertEqual(i["material_name"], j["material"])
            self.assertEqual(i["file_bytes"], j["file_bytes"])
            self.assertEqual(a.positions.shape, (6, 3))
            self.assertEqual(a.triangles.shape, (8, 3))
            self.assertTrue((a.triangles < 6).all())
            # an octahedron: every vertex at the same distance from the centre
            r = np.linalg.norm(a.positions - a.positions.mean(axis=0), axis=1)
            self.assertLess(np.ptp(r), 1e-6 * r.max())
            n = np.linalg.norm(a.normals, axis=1)
            np.testing.assert_allclose(n, 1.0, rtol=1e-6)
            self.assertEqual(a.params["mesh"], j["params"]["mesh"])

    def test_decode_matches_the_c_decoder(self):
        with sss.open(GOLDEN) as a:
            for light in LIGHTS:
                q = a.decode(light)
                self.assertEqual(q.shape, (6, 3))
                self.assertEqual(q.dtype, np.float32)
                for v in range(6):
                    np.testing.assert_array_equal(q[v], stat_q(GOLDEN, v, light))


class Baked(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        Files.make()

    def test_default_bake_with_near_terms_matches_sss_stat(self):
        with sss.open(Files.default) as a:
            i = a.info
            self.assertEqual(i["quant_name"], "refs")
            self.assertEqual(i["near_terms"], 1)
            for light in LIGHTS[:2]:
                q = a.decode(light)
                self.assertTrue(np.isfinite(q).all() and (q >= 0).all())
                for v in (0, a.nv // 2, a.nv - 1):
                    np.testing.assert_array_equal(q[v], stat_q(Files.default, v, light))

    def test_range_is_the_slice_and_bytes_equal_path(self):
        data = open(Files.default, "rb").read()
        with sss.open(Files.default) as a, sss.open_bytes(data, "blob-in-memory") as b:
            self.assertEqual(a.info["nv"], b.info["nv"])
            np.testing.assert_array_equal(a.positions, b.positions)
            light = LIGHTS[1]
            whole = a.decode(light)
            np.testing.assert_array_equal(whole, b.decode(light))
            np.testing.assert_array_equal(whole[10:30], a.decode(light, first=10, count=20))

    def test_given_visibility_is_used(self):
        with sss.open(Files.default) as a:
            light = LIGHTS[2]
            lit = a.visibility(light)
            self.assertEqual(lit.shape, (a.nv,))
            self.assertTrue(0 < lit.sum() < a.nv)
            np.testing.assert_array_equal(a.decode(light), a.decode(light, lit=lit))
            # no vertex lit: only the far rows remain, never more than with the near terms
            dark = a.decode(light, lit=np.zeros(a.nv, np.uint8))
            self.assertTrue((dark <= a.decode(light) + 1e-7).all())
            self.assertLess(dark.sum(), a.decode(light).sum())

    def test_decode_error(self):
        with sss.open(Files.default) as a, sss.open(Files.float) as f:
            same = sss.decode_error(f, f, ndirs=20)
            self.assertEqual(same["max_abs"], 0.0)
            e = sss.decode_error(a, f, ndirs=20)
            self.assertEqual(len(e["rms"]), 4)
            self.assertGreater(e["rms"][3], 0.0)
            self.assertLess(e["rel_rms"][3], 0.5)

    def test_errors_name_the_file(self):
        missing = os.path.join(TMP, "missing.sss")
        with self.assertRaises(sss.SSSError) as c:
            sss.open(missing)
        self.assertIn("missing.sss", str(c.exception))
        data = open(Files.float, "rb").read()
        with self.assertRaises(sss.SSSError) as c:
            sss.open_bytes(data[:200], "cut.sss")
        self.assertIn("cut.sss", str(c.exception))
        with sss.open(Files.float) as a:
            with self.assertRaises(sss.SSSError):
                a.decode((0, 0, 0))
            with self.assertRaises(sss.SSSError):
                a.decode((0, 0, 1), first=a.nv, count=1)
            with self.assertRaises(ValueError):
                a.decode((0, 1))
            with self.assertRaises(sss.SSSError):
                a.decode_point((0, 0, 5))  # not baked for point lights
        with sss.open(GOLDEN) as g, self.assertRaises(sss.SSSError):
            g.visibility((0, 0, 1))  # no run-time near terms: nothing to trace
        a.close()
        with self.assertRaises(ValueError):
            a.decode((0, 0, 1))

    def test_example_script_runs(self):
        out = os.path.join(TMP, "example")
        script = os.path.join(os.environ["SSS_SOURCE"], "examples", "python", "error_vs_bytes.py")
        r = subprocess.run([sys.executable, script, Files.mesh, out, "--quick"], capture_output=True, text=True)
        self.assertEqual(r.returncode, 0, r.stderr)
        rows = open(os.path.join(out, "error_vs_bytes.csv")).read().splitlines()
        self.assertGreaterEqual(len(rows), 4)
        self.assertTrue(os.path.getsize(os.path.join(out, "error_vs_bytes.png")) > 1000)

    def test_info_has_the_phase(self):
        """g of section PHAS (docs/layers.md §2) and the layer counts."""
        Files.make()
        with sss.open(Files.default) as a:
            i = a.info
            self.assertEqual((i["g"], i["nlayers"], i["layer_depths"]), (0.0, 0, 0))
        path = os.path.join(TMP, "phase.sss")
        run(os.environ["SSS_BAKE"], Files.mesh, "-o", path, "--sigma-a", "0.6,0.6,0.6", "--sigma-s", "2,1,1",
            "--g", "0.25", "--mm-per-unit", 20, "--dirs", 20, "-q")
        with sss.open(path) as a:
            self.assertEqual(a.info["g"], 0.25)
            self.assertEqual(a.info["sigmap_s"][0], 1.5)  # sigma'_s = sigma_s (1 - g)
            self.assertEqual(a.info["version_minor"], 8)


if __name__ == "__main__":
    unittest.main(verbosity=2)
