"""What a new user meets at the command line, held to the rules of ``run``.

What is proven: ``sweepcore basins -o`` refuses what ``run`` refuses (a read-only
file, a symbolic link, a FIFO, a directory), before any work and leaving it as it
was; ``simulate`` names every term of the law it ran (damping, Stribeck terms) in
its summary and title; ``info`` reads a subcritical Hopf point's measured boundary
as the fold it is; ``plot`` refuses options its picture would ignore; Ctrl-C says
what each command leaves; a study's misspelt key gets the API's "did you mean";
``simulate --help`` says why its tolerance is tighter than run's.
"""
import os
import stat

import numpy as np
import pytest

import sweepcore as sc
from sweepcore.cli import main

from conftest import BSTAB_AXES

STUDY = BSTAB_AXES + 'v = [1.3, 1.6]\n[basins]\nroute = "exact"\n'


def run(argv, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    code = main(argv)
    return code, capsys.readouterr()


def _read_only(path):
    path.write_text("an earlier result")
    path.chmod(0o444)


def _link(path):
    (path.parent / "target.txt").write_text("an earlier result")
    path.symlink_to("target.txt")


@pytest.mark.parametrize("make, message", [
    (_read_only, r"is a read-only file \(mode 0444\); pass overwrite=True"),
    (_link, "is a symbolic link, not a regular file"),
    (lambda p: os.mkfifo(p), "is a FIFO, not a regular file"),
    (lambda p: p.mkdir(), "is a directory; give the name of the result file"),
], ids=["read-only", "symlink", "fifo", "directory"])
def test_basins_output_follows_the_path_rules_of_run(make, message, tmp_path,
                                                     monkeypatch, capsys):
    (tmp_path / "s.toml").write_text(STUDY)
    target = tmp_path / "F.nc"
    make(target)
    before = os.lstat(target)
    code, out = run(["basins", "s.toml", "-o", "F.nc", "--no-png"], tmp_path,
                    monkeypatch, capsys)
    assert code == 2, out.err
    assert "sweepcore basins: error: path='F.nc' " in out.err
    import re
    assert re.search(message, out.err), out.err
    after = os.lstat(target)
    assert (after.st_mode, after.st_ino, after.st_mtime_ns) == \
        (before.st_mode, before.st_ino, before.st_mtime_ns)
    if stat.S_ISREG(before.st_mode) or stat.S_ISLNK(before.st_mode):
        assert (tmp_path / ("target.txt" if stat.S_ISLNK(before.st_mode) else "F.nc")
                ).read_text() == "an earlier result"
    assert not [p for p in tmp_path.iterdir() if ".partial" in p.name]   # no work


LAW = ["--m", "1", "--k", "1", "--r-y", "1", "--v", "1.5", "--t-end", "5"]


def test_simulate_names_damping_and_stribeck_terms(tmp_path, monkeypatch, capsys):
    """A Stribeck run with damping must not read as constant Coulomb friction: the
    summary's slider line and the picture's title name c, r_k and v_s (and leave
    them out where the law has no such term)."""
    code, out = run(["simulate", *LAW, "--r-k", "0.5", "--v-s", "0.5", "--c", "0.1",
                     "-o", "s.nc"], tmp_path, monkeypatch, capsys)
    assert code == 0, out.err
    slider = next(ln for ln in out.out.splitlines() if ln.startswith("  slider:"))
    assert "c = 0.1 kN s cm-1, r_k = 0.5 kN, v_s = 0.5 cm s-1" in slider
    title = sc.plot_trajectory(sc.open_result(tmp_path / "s.nc"))._suptitle.get_text()
    assert "$c$ = 0.1" in title and "$r_k$ = 0.5" in title and "$v_s$ = 0.5" in title
    code, out = run(["simulate", *LAW], tmp_path, monkeypatch, capsys)
    slider = next(ln for ln in out.out.splitlines() if ln.startswith("  slider:"))
    assert " c = " not in slider and "r_k" not in slider and "v_s" not in slider


def test_info_reads_a_subcritical_boundary_as_the_fold(tmp_path, monkeypatch, capsys):
    """From the stuck start a Stribeck slider keeps its stick-slip cycle above its
    subcritical Hopf point v* = v_s ln((r_y - r_k)/(v_s c)): info says the measured
    boundary lies above v* and why, with the file's numbers, not a bare
    |v_measured - v*| that reads like an error."""
    path = tmp_path / "m.nc"
    sc.sweep(sc.Grid(m=1.0, k=1.0, r_y=1.0, r_k=0.5, v_s=0.5, c=[0.1, 0.2],
                     v=np.linspace(1.0, 2.2, 13)), path=path, progress=False).close()
    code, out = run(["info", "m.nc"], tmp_path, monkeypatch, capsys)
    assert code == 0
    assert "|v_measured - v*|" not in out.out
    ds = sc.open_result(path)
    vstar = 0.5 * np.log(1.0 / np.array([0.1, 0.2]))         # closed form
    np.testing.assert_allclose(ds.v_star.values, vstar, rtol=1e-12)
    d = ds.v_hopf_measured.values - vstar
    assert (d > 0).all()
    assert (f"where the Hopf point is subcritical (2 rows) v_measured - v* in "
            f"[{d.min():.3g}, {d.max():.3g}] cm s-1: above v*") in out.out


def test_plot_refuses_options_the_picture_would_ignore(tmp_path, monkeypatch, capsys):
    code, out = run(["simulate", *LAW, "-o", "s.nc"], tmp_path, monkeypatch, capsys)
    assert code == 0
    for option in (["--variables", "amplitude"], ["--x", "v"]):
        code, out = run(["plot", "s.nc", *option], tmp_path, monkeypatch, capsys)
        assert code == 2
        assert f"{option[0]}: s.nc holds a simulation" in out.err
        assert not (tmp_path / "s.png").exists()


@pytest.mark.parametrize("argv, where, said", [
    (["plot", "s.nc"], "sweepcore.plot.save",
     "sweepcore plot: interrupted (while drawing; s.png not written)"),
    (["simulate", *LAW, "-o", "t.nc"], "sweepcore.simulate.simulate",
     "sweepcore simulate: interrupted (nothing written)"),
    (["export", "s.nc", "--csv", "s.csv"], "sweepcore.cli.commands.csv_tables",
     "sweepcore export: interrupted (nothing written)"),
])
def test_ctrl_c_says_what_the_command_leaves(argv, where, said, tmp_path, monkeypatch,
                                             capsys):
    assert run(["simulate", *LAW, "-o", "s.nc"], tmp_path, monkeypatch, capsys)[0] == 0
    module, name = where.rsplit(".", 1)

    def ctrl_c(*a, **k):
        raise KeyboardInterrupt
    import importlib
    monkeypatch.setattr(importlib.import_module(module), name, ctrl_c)
    code, out = run(argv, tmp_path, monkeypatch, capsys)
    assert code == 130
    assert out.err.strip() == said
    assert "resume a sweep" not in out.err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.nc"]


def test_ctrl_c_while_a_run_draws_says_the_result_is_complete(tmp_path, monkeypatch,
                                                              capsys):
    (tmp_path / "s.toml").write_text(STUDY.split("[basins]")[0])

    def ctrl_c(*a, **k):
        raise KeyboardInterrupt
    monkeypatch.setattr("sweepcore.plot.save", ctrl_c)
    code, out = run(["run", "s.toml", "-q"], tmp_path, monkeypatch, capsys)
    assert code == 130
    assert out.err.strip() == ("sweepcore run: interrupted (while drawing; the result "
                               "s.nc is complete, `sweepcore plot s.nc -o s.png` draws "
                               "it)")
    assert sc.open_result(tmp_path / "s.nc").sizes["v"] == 2


def test_a_misspelt_study_key_gets_the_apis_suggestion(tmp_path, monkeypatch, capsys):
    (tmp_path / "s.toml").write_text(STUDY + "[solver]\ntolerance = 1e-8\n")
    code, out = run(["basins", "s.toml"], tmp_path, monkeypatch, capsys)
    assert code == 2
    assert ("s.toml:12: solver.tolerance: unknown key 'tolerance' in [solver]; did you "
            "mean 'tol'?") in out.err
    with pytest.raises(TypeError, match="did you mean 'tol'"):      # as Python says
        sc.sweep(sc.Grid(m=1.0, k=1.0, r_y=1.0, v=1.0), tolerance=1e-8)


def test_simulate_help_says_why_its_tolerance_is_tighter(capsys):
    with pytest.raises(SystemExit):
        main(["simulate", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "default 1e-10, tighter than run's 1e-8: a time history carries the error " \
           "of every step to t_end" in text
    import inspect
    doc = " ".join(inspect.getdoc(sc.simulate).split())
    assert "``tol`` defaults to 1e-10, tighter than the 1e-8 of" in doc


def test_simulate_refuses_an_empty_law_table_by_name(tmp_path, monkeypatch, capsys):
    """``--law-table ''`` is refused as an empty path, named as given (it said
    "'.' is a directory": Path("") is "."); so is ``TableLaw.from_csv("")``."""
    code, out = run(["simulate", "--m", "1", "--k", "1", "--v", "1", "--law-table",
                     ""], tmp_path, monkeypatch, capsys)
    assert code == 2
    assert "--law-table '': the path is empty" in out.err
    assert "directory" not in out.err
    with pytest.raises(OSError) as err:
        sc.TableLaw.from_csv("")
    assert str(err.value).startswith("cannot read the friction table '': No such file")
