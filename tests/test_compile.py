"""Compiles are announced, can be made ahead of time, and a cache never breaks a run.

What is proven:
* from Python, a kernel that compiles says so on stderr (what, and the time it
  took), and ``logging.getLogger("sweepcore.compile")`` silences it;
* ``sweepcore.compile`` / ``sweepcore compile`` compile each entry kernel for the
  argument types the Python rooms call it with (else the cache would never be hit:
  no error, only the time lost), and refuse an unknown kind or method by name;
* a truncated kernel cache file is recompiled with a line that says so, and the
  run's answer is the closed form's; later runs load it again;
* a cache directory that cannot be written costs the cache only: no compiled file
  is written anywhere else (numba's fallback was the package's ``__pycache__``);
* (slow) compiling the main job's attractor kernel and a forced kernel from an
  empty cache compiles none of sweepcore's kernels for a second signature.

Each cold case runs in a subprocess with a fresh ``SWEEPCORE_CACHE_DIR``; the
cheapest kernel serves (the derived quantities of a Leine law, ~10 s cold).
"""
import math
import re
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from numba import typeof

import sweepcore as sc
from sweepcore import compiled
from sweepcore._kernels import derived, entries, layout

PACKAGE = Path(sc.__file__).resolve().parent
ROOT = PACKAGE.parent
# the Hopf speed of Leine's law with damping c: c + F'(-u) = 0 with
# F' = -f_s delta/(1 + delta u)^2, so u = (sqrt(f_s delta/c) - 1)/delta
F_S, DELTA, C = 1.0, 3.0, 0.1
HOPF = (math.sqrt(F_S * DELTA / C) - 1.0) / DELTA
PROBE = f"""
import sweepcore as sc
p = sc.Params(m=1.0, k=1.0, c={C}, v=0.5, law=sc.LeineLaw(f_s={F_S}, delta={DELTA}))
print(repr(p.hopf_speeds[0]))
"""


def _run(code: str, cache, **env):
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=600, env={**os.environ, "SWEEPCORE_CACHE_DIR": str(cache),
                                           **env})
    assert out.returncode == 0, out.stderr
    return out


def _compiled_files():
    return sorted(p for ext in ("*.nbi", "*.nbc") for p in PACKAGE.rglob(ext))


def test_a_compile_from_python_is_announced_and_can_be_silenced(tmp_path):
    """What compiles, with a line while it lasts (every ``compiled.TICK`` s: here a
    tenth of a second) and the time it took, from Python as from the command line."""
    cold = _run("import sweepcore.compiled\nsweepcore.compiled.TICK = 0.1\n" + PROBE,
                tmp_path)
    assert float(cold.stdout) == pytest.approx(HOPF, rel=1e-9)
    assert "sweepcore: compiling the derived_rows kernel" in cold.stderr
    assert "sweepcore: ... compiling, " in cold.stderr
    assert "sweepcore: compiled the derived_rows kernel in " in cold.stderr
    # the table kind compiles its own kernel: silenced, nothing on stderr
    silent = _run("import logging\nlogging.getLogger('sweepcore.compile')"
                  ".setLevel(logging.ERROR)\nimport numpy as np, sweepcore as sc\n"
                  "law = sc.TableLaw(np.linspace(0, 2, 7), np.linspace(1, 0.7, 7))\n"
                  "print(sc.Params(m=1.0, k=1.0, v=0.5, law=law).x_eq)", tmp_path)
    assert silent.stderr == ""
    warm = _run(PROBE, tmp_path)
    assert "compil" not in warm.stderr


def test_a_damaged_cache_file_is_recompiled_with_a_line(tmp_path):
    _run(PROBE, tmp_path)
    data = [p for p in tmp_path.rglob("derived.derived_rows-*.nbc")]
    assert data
    for path in data:               # a write cut short
        path.write_bytes(path.read_bytes()[:64])
    again = _run(PROBE, tmp_path)
    assert float(again.stdout) == pytest.approx(HOPF, rel=1e-9)
    assert "is damaged (UnpicklingError" in again.stderr
    assert "sweepcore: compiling the derived_rows kernel" in again.stderr
    index = next(tmp_path.rglob("derived.derived_rows-*.nbi"))
    index.write_bytes(b"\x80\x04garbage")      # a garbled index
    third = _run(PROBE, tmp_path)
    assert float(third.stdout) == pytest.approx(HOPF, rel=1e-9)
    assert "is damaged" in third.stderr
    assert "compil" not in _run(PROBE, tmp_path).stderr     # rewritten: loads


def test_an_unwritable_cache_writes_nothing_elsewhere(tmp_path):
    before = _compiled_files()
    blocked = tmp_path / "file"
    blocked.write_text("a file where the cache directory would be")
    out = _run(PROBE, blocked)
    assert float(out.stdout) == pytest.approx(HOPF, rel=1e-9)
    assert "cannot be written" in out.stderr
    assert _compiled_files() == before


def test_ahead_of_time_signatures_are_the_calls(monkeypatch):
    """The types ``compiled.compile_kernels`` compiles each entry for are the types
    the rooms call it with: every call recorded (and stopped before it runs)."""
    seen = {}
    real = entries.entry

    class Stop(Exception):
        pass

    def recorder(name, meth):
        kernel = real(name, meth)

        def call(*args):
            seen[name] = tuple(typeof(a) for a in args)
            if name == "options":
                return kernel(*args)
            raise Stop
        return call

    def derived_rows(*args):
        seen["derived_rows"] = tuple(typeof(a) for a in args)
        raise Stop

    monkeypatch.setattr(entries, "entry", recorder)
    monkeypatch.setattr(derived, "derived_rows", derived_rows)
    law = sc.LeineLaw(f_s=F_S, delta=DELTA)
    p = sc.Params(m=1.0, k=1.0, c=C, v=0.5, law=law)
    grid = sc.Grid(m=1.0, k=1.0, c=C, v=[0.4, 0.5], law=law)
    for call in (lambda: sc.attractor(p, method="rk4"),
                 lambda: sc.simulate(p, t_end=1.0, method="rk4"),
                 lambda: sc.slip_cycles(grid, method="rk4"),
                 lambda: p.hopf_speeds):
        with pytest.raises(Stop):
            call()
    lw = law.data()
    unforced = [name for name in compiled.ENTRIES if name not in compiled.FORCED_ENTRIES]
    want = {name: tuple(typeof(a) for a in compiled._arguments(name, lw))
            for name in unforced}
    assert {name: seen[name] for name in unforced} == want
    # and a forced slider's: its load's data in the excitation's place
    derived_types = seen["derived_rows"]
    seen.clear()
    seen["derived_rows"] = derived_types
    forced = sc.Params(m=1.0, k=1.0, c=C, v=0.5, law=law, F0=1.0, Omega=1.2)
    for call in (lambda: sc.attractor(forced, method="rk4"),
                 lambda: sc.simulate(forced, t_end=1.0, method="rk4")):
        with pytest.raises(Stop):
            call()
    ex = forced.loads[0].data()
    for name in ("forced_rows", "trajectory", "options"):
        assert seen[name] == tuple(typeof(a) for a in compiled._arguments(name, lw, ex))
    assert seen["derived_rows"] == (typeof(np.zeros((1, layout.NP))), typeof(lw), typeof(0),
                                    typeof(np.zeros(1)))


def test_unknown_kind_or_method_is_refused_by_name(capsys):
    with pytest.raises(ValueError, match=r"law must be one of .*got 'tabel'.*table"):
        sc.compile(law="tabel")
    with pytest.raises(ValueError, match=r"method must be one of .*got 'auto'"):
        sc.compile(method="auto")
    from sweepcore.cli import main
    with pytest.raises(SystemExit) as stop:       # argparse's refusal
        main(["compile", "--law", "lein"])
    assert stop.value.code == 2
    assert "invalid choice: 'lein'" in capsys.readouterr().err


@pytest.mark.slow
def test_the_compile_command_fills_the_cache(tmp_path):
    """``sweepcore compile --law leine --method rk4`` (about 1 min cold), then a
    run of that kind and method, autonomous and forced, compiles nothing."""
    out = subprocess.run([sys.executable, "-m", "sweepcore", "compile", "--law", "leine",
                          "--method", "rk4"], capture_output=True, text=True,
                         env={**os.environ, "SWEEPCORE_CACHE_DIR": str(tmp_path)})
    assert out.returncode == 0, out.stderr
    said = re.findall(r"sweepcore: compiled the (.+?) kernel", out.stderr)
    assert f"{len(said)} kernel(s) compiled" in out.stdout
    assert {"attractor", "forced response", "stroboscopic image"} <= set(said), said
    after = _run(PROBE + "p = sc.Params(m=1.0, k=1.0, v=0.2, law=sc.LeineLaw(1.0, 3.0))\n"
                 "print(sc.attractor(p, method='rk4').regime)\n"
                 "print(sc.simulate(p, t_end=5.0, method='rk4').attrs['status'])\n"
                 "f = sc.Params(m=1.0, k=1.0, v=0.2, law=sc.LeineLaw(1.0, 3.0), F0=0.5,"
                 " Omega=1.3)\n"
                 "print(sc.attractor(f, method='rk4').regime)\n"
                 "print(sc.simulate(f, t_end=5.0, method='rk4').attrs['status'])",
                 tmp_path)
    assert "compil" not in after.stderr


@pytest.mark.slow
def test_no_kernel_is_compiled_twice_in_one_entry():
    """From an empty cache, the attractor kernel of the main job (``sweepcore run
    studies/hopf_map.toml``: dop853, polynomial law) and the forced kernel compile
    each of sweepcore's kernels for one signature. A second one (a constant typed as
    its literal value, an int where other calls pass a float: ``_kernels/jit.py``)
    compiles that kernel and everything it calls once more. numba's compile events,
    recorded by ``benchmarks/compile_probe.py --breakdown`` in a fresh process
    (~80 s of CPU)."""
    if str(ROOT) not in sys.path:
        sys.path.insert(0, str(ROOT))
    from benchmarks import compile_probe
    lines = list(compile_probe.breakdown_fresh(
        ["attractor_rows", "dop853", "polynomial", "forced_rows", "dop853", "polynomial"]))
    assert [line["entry"] for line in lines] == ["attractor_rows", "forced_rows"]
    for line in lines:
        assert line["functions_compiled"] > 10, line        # it did compile, cold
        assert line["kernels_compiled_more_than_once"] == {}, line["entry"]
