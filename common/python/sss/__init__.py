"""sss: read baked translucency files (.sss) from Python.

A thin ctypes layer over libsss's runtime API (common/include/sss/api.h,
docs/api.md): the geometry as numpy arrays, q(x_v, w) decoded for any light
exactly as the C decoder does (the very same calls), the file's description,
and the error measurements (docs/python.md).

    import sss
    a = sss.open("dragon.sss")
    q = a.decode([0.3, 0.4, 0.87])       # (nv, channels) float32
    a.positions, a.triangles, a.info     # numpy arrays, dict

The shared library is found through $SSS_LIBRARY (a path), next to an
installed package (PREFIX/lib/.../libsss.so.*), or by the linker's search
(ctypes.util.find_library("sss")).
"""
import ctypes
import ctypes.util
import glob
import json
import os
import subprocess

import numpy as np

__all__ = ["Asset", "SSSError", "open", "open_bytes", "decode_error", "stat", "library_path"]

_u32, _u64, _f64, _f32 = ctypes.c_uint32, ctypes.c_uint64, ctypes.c_double, ctypes.c_float
_NAME_MAX = 16


class _Error(ctypes.Structure):  # sss_error (sss/result.h)
    _fields_ = [("msg", ctypes.c_char * 512)]


class _Desc(ctypes.Structure):  # sss_asset_desc (sss/api.h), field for field
    _fields_ = [
        ("nv", _u32), ("nf", _u32), ("channels", _u32), ("quant", _u32),
        ("quant_name", ctypes.c_char * _NAME_MAX), ("sh_order", _u32),
        ("sh_kind_name", ctypes.c_char * _NAME_MAX), ("ndirs", _u32), ("effects", _u32),
        ("has_dir_set", _u32), ("near_terms", _u32), ("near_rings", _u32), ("near_radius_mm", _f64),
        ("nexact", _u32), ("nshells", _u32), ("env_order", _u32),
        ("version_major", _u32), ("version_minor", _u32), ("file_bytes", _u64),
        ("integral_bytes_per_vertex", _f64), ("mm_per_unit", _f64),
        ("material_name", ctypes.c_char * 32), ("sigma_a", _f64 * 3), ("sigmap_s", _f64 * 3), ("eta", _f64),
        ("g", _f64), ("nlayers", _u32), ("layer_depths", _u32),
    ]


class SSSError(Exception):
    """A libsss call failed; the message is libsss's one line (file and element)."""

    def __init__(self, code, message):
        super().__init__(message)
        self.code = code


def library_path():
    """The shared libsss this package loads (see the module's doc)."""
    env = os.environ.get("SSS_LIBRARY")
    if env:
        return env
    here = os.path.dirname(os.path.abspath(__file__))
    # installed: PREFIX/LIBDIR/python3/dist-packages/sss → PREFIX/LIBDIR/libsss.so.*
    for up in ("../../..", "../../../.."):
        found = sorted(glob.glob(os.path.join(here, up, "libsss.so*")))
        if found:
            return os.path.normpath(found[0])
    name = ctypes.util.find_library("sss")
    if name:
        return name
    raise OSError("sss: libsss.so not found: set SSS_LIBRARY to its path (docs/python.md)")


_lib = None


def _L():
    """libsss with the prototypes of the calls used here, loaded once."""
    global _lib
    if _lib is not None:
        return _lib
    lib = ctypes.CDLL(library_path())
    P, E = ctypes.c_void_p, ctypes.POINTER(_Error)
    dp, fp, bp = ctypes.POINTER(_f64), ctypes.POINTER(_f32), ctypes.POINTER(ctypes.c_uint8)
    sig = {
        "sss_asset_open": ([ctypes.c_char_p, ctypes.POINTER(P), E], ctypes.c_int),
        "sss_asset_open_memory": ([ctypes.c_char_p, ctypes.c_size_t, ctypes.c_char_p, ctypes.POINTER(P), E], ctypes.c_int),
        "sss_asset_close": ([P], None),
        "sss_asset_info": ([P, ctypes.POINTER(_Desc), E], ctypes.c_int),
        "sss_asset_name": ([P], ctypes.c_char_p),
        "sss_asset_positions": ([P], fp),
        "sss_asset_normals": ([P], fp),
        "sss_asset_triangles": ([P], ctypes.POINTER(_u32)),
        "sss_asset_params_json": ([P], ctypes.c_char_p),
        "sss_asset_file": ([P], P),
        "sss_asset_decode": ([P, dp, _u32, _u32, bp, fp, E], ctypes.c_int),
        "sss_asset_visibility": ([P, dp, bp, E], ctypes.c_int),
        "sss_asset_exact_direction": ([P, _u32, dp, E], ctypes.c_int),
        "sss_asset_decode_exact": ([P, _u32, _u32, _u32, fp, E], ctypes.c_int),
        "sss_asset_decode_point": ([P, dp, _u32, _u32, fp, E], ctypes.c_int),
        "sss_asset_decode_env": ([P, fp, _u32, _u32, fp, E], ctypes.c_int),
        "sss_decode_error": ([P, P, _u32, _u64, dp, dp, dp, E], ctypes.c_int),
        "sss_result_string": ([ctypes.c_int], ctypes.c_char_p),
    }
    for name, (args, res) in sig.items():
        fn = getattr(lib, name)
        fn.argtypes, fn.restype = args, res
    _lib = lib
    return lib


def _check(rc, err):
    if rc != 0:
        msg = err.msg.decode("utf-8", "replace") or _L().sss_result_string(rc).decode()
        raise SSSError(rc, msg)


def _vec3(v, what):
    a = np.ascontiguousarray(v, dtype=np.float64).reshape(-1)
    if a.shape != (3,):
        raise ValueError(f"sss: {what} must have 3 components, got {a.size}")
    return a


def _dptr(a):
    return a.ctypes.data_as(ctypes.POINTER(_f64))


class Asset:
    """An opened .sss file (sss_asset). Decoding calls may run on several
    threads at once (sss/api.h: thread-safe per call); close() or the end of
    a with-block frees it."""

    def __init__(self, handle, keep=None):
        self._h = handle
        self._keep = keep
        info = _Desc()
        err = _Error()
        _check(_L().sss_asset_info(self._h, ctypes.byref(info), ctypes.byref(err)), err)
        self._d = info

    # --- lifetime ---------------------------------------------------------
    def close(self):
        if self._h:
            _L().sss_asset_close(self._h)
            self._h = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        try:
            self.close()
        except Exception:
            pass

    def _handle(self):
        if not self._h:
            raise ValueError("sss: the asset is closed")
        return self._h

    # --- what the file holds ----------------------------------------------
    @property
    def nv(self):
        return self._d.nv

    @property
    def channels(self):
        return self._d.channels

    @property
    def info(self):
        """sss_asset_desc as a dict (counts, storage form, effects, bytes, material)."""
        d = self._d
        out = {}
        for name, _ in _Desc._fields_:
            v = getattr(d, name)
            if isinstance(v, bytes):
                v = v.decode()
            elif not isinstance(v, (int, float)):
                v = list(v)[: d.channels]
            out[name] = v
        out["name"] = _L().sss_asset_name(self._handle()).decode()
        return out

    @property
    def params(self):
        """The bake parameters the file records (PARM, JSON) as a dict."""
        s = _L().sss_asset_params_json(self._handle())
        return json.loads(s.decode()) if s else {}

    @property
    def positions(self):
        """(nv, 3) float32 vertex positions in mesh units (a copy)."""
        p = _L().sss_asset_positions(self._handle())
        return np.ctypeslib.as_array(p, shape=(self.nv, 3)).copy()

    @property
    def normals(self):
        """(nv, 3) float32 unit vertex normals (a copy)."""
        p = _L().sss_asset_normals(self._handle())
        return np.ctypeslib.as_array(p, shape=(self.nv, 3)).copy()

    @property
    def triangles(self):
        """(nf, 3) uint32 vertex indices, counter-clockwise seen from outside (a copy)."""
        p = _L().sss_asset_triangles(self._handle())
        return np.ctypeslib.as_array(p, shape=(self._d.nf, 3)).copy()

    # --- decoding -----------------------------------------------------------
    def _range(self, first, count):
        if count is None:
            count = self.nv - first
        out = np.empty((count, self.channels), dtype=np.float32)
        return int(first), int(count), out

    def decode(self, light, first=0, count=None, lit=None):
        """q(x_v, w) per unit irradiance for a directional light from `light`
        (towards the light, mesh space, any length) for vertices
        [first, first + count): a (count, channels) float32 array, the value
        the viewer shows (stored rows plus run-time near terms). `lit`: the
        vertices' own visibility (nv values, nonzero = lit) for files with
        run-time near terms; None lets libsss trace the bake's rays."""
        l = _vec3(light, "light")
        first, count, out = self._range(first, count)
        litp = None
        if lit is not None:
            litv = np.ascontiguousarray(lit, dtype=np.uint8).reshape(-1)
            if litv.size != self.nv:
                raise ValueError(f"sss: lit must have {self.nv} values, got {litv.size}")
            litp = litv.ctypes.data_as(ctypes.POINTER(ctypes.c_uint8))
        err = _Error()
        rc = _L().sss_asset_decode(self._handle(), _dptr(l), first, count, litp,
                                   out.ctypes.data_as(ctypes.POINTER(_f32)), ctypes.byref(err))
        _check(rc, err)
        return out

    def visibility(self, light):
        """The own visibility libsss traces for `light` ((nv,) uint8, 1 = lit);
        files with run-time near terms only."""
        l = _vec3(light, "light")
        lit = np.empty(self.nv, dtype=np.uint8)
        err = _Error()
        _check(_L().sss_asset_visibility(self._handle(), _dptr(l), lit.ctypes.data_as(ctypes.POINTER(ctypes.c_uint8)),
                                         ctypes.byref(err)), err)
        return lit

    def exact_direction(self, index):
        """Direction towards static light `index` of a scene bake (QDIR)."""
        d = np.empty(3, dtype=np.float64)
        err = _Error()
        _check(_L().sss_asset_exact_direction(self._handle(), int(index), _dptr(d), ctypes.byref(err)), err)
        return d

    def decode_exact(self, index, first=0, count=None):
        """q for static directional light `index` (QDIR), per unit intensity."""
        first, count, out = self._range(first, count)
        err = _Error()
        _check(_L().sss_asset_decode_exact(self._handle(), int(index), first, count,
                                           out.ctypes.data_as(ctypes.POINTER(_f32)), ctypes.byref(err)), err)
        return out

    def decode_point(self, position, first=0, count=None):
        """q for a point light at `position` (mesh units) from the shells (PSHL)."""
        p = _vec3(position, "position")
        first, count, out = self._range(first, count)
        err = _Error()
        _check(_L().sss_asset_decode_point(self._handle(), _dptr(p), first, count,
                                           out.ctypes.data_as(ctypes.POINTER(_f32)), ctypes.byref(err)), err)
        return out

    def decode_env(self, probe=None, first=0, count=None):
        """Environment lighting from the SH transfer (ENVT): `probe` is
        3 x order^2 radiance SH coefficients (None: the probe of the bake)."""
        first, count, out = self._range(first, count)
        pp = None
        if probe is not None:
            k = self._d.env_order ** 2
            pv = np.ascontiguousarray(probe, dtype=np.float32).reshape(-1)
            if pv.size != 3 * k:
                raise ValueError(f"sss: probe must have {3 * k} coefficients, got {pv.size}")
            pp = pv.ctypes.data_as(ctypes.POINTER(_f32))
        err = _Error()
        _check(_L().sss_asset_decode_env(self._handle(), pp, first, count,
                                         out.ctypes.data_as(ctypes.POINTER(_f32)), ctypes.byref(err)), err)
        return out


def open(path):  # noqa: A001 (the package's verb, as in the C API)
    """Opens the .sss file at `path` (checked whole; SSSError names the file
    and the element on bad input)."""
    h = ctypes.c_void_p()
    err = _Error()
    _check(_L().sss_asset_open(os.fsencode(path), ctypes.byref(h), ctypes.byref(err)), err)
    return Asset(h)


def open_bytes(data, name="memory"):
    """The same from the bytes of a file (`name` labels errors)."""
    data = bytes(data)
    h = ctypes.c_void_p()
    err = _Error()
    _check(_L().sss_asset_open_memory(data, len(data), name.encode(), ctypes.byref(h), ctypes.byref(err)), err)
    return Asset(h)


def decode_error(approx, ref, ndirs=100, seed=1):
    """Per-vertex error of `approx` against `ref` (two Assets of one mesh and
    channel count, e.g. a compressed bake against a float one) over `ndirs`
    random light directions, both decoded from their stored rows
    (sss_decode_error, docs/accuracy.md): dict of area-weighted rms and
    rel_rms per channel (last entry: all channels) and max_abs."""
    c = approx.channels
    rel = np.zeros(c + 1)
    rms = np.zeros(c + 1)
    mx = ctypes.c_double(0.0)
    err = _Error()
    L = _L()
    rc = L.sss_decode_error(L.sss_asset_file(approx._handle()), L.sss_asset_file(ref._handle()), int(ndirs),
                            int(seed), _dptr(rel), _dptr(rms), ctypes.byref(mx), ctypes.byref(err))
    _check(rc, err)
    return {"rms": rms.tolist(), "rel_rms": rel.tolist(), "max_abs": mx.value}


def stat(path, *args, tool=None):
    """`sss-stat PATH ARGS... --json` as a dict: the measurements that need
    the exact evaluator or the renderer (--error for the per-vertex and
    image-space error against the exact q, --query V --light X,Y,Z,
    --model-error against the path-traced reference). `tool`: the sss-stat
    to run (default $SSS_STAT, else sss-stat on PATH). Raises SSSError with
    the tool's one-line message when it fails."""
    exe = tool or os.environ.get("SSS_STAT") or "sss-stat"
    r = subprocess.run([exe, os.fspath(path), *map(str, args), "--json"], capture_output=True, text=True)
    if r.returncode != 0:
        raise SSSError(r.returncode, r.stderr.strip().splitlines()[-1] if r.stderr.strip() else f"{exe} failed")
    return json.loads(r.stdout)
