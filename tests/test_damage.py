"""Damaged and hostile files: refused or repaired, never read back as plausible data
and never a hang.

What is proven, one hostile probe each: a bit flipped in a finished
file's coordinate fails its Fletcher-32 checksum on ``open_result`` (the same flip
in a file written without checksums is read back silently, so the test can fail);
``open_result`` and ``sweepcore info`` name an empty name, a directory, a FIFO
(without blocking) and a truncated file; ``sweepcore run`` on a FIFO study returns;
a temporary left by a write killed before its rename is removed by the next sweep
on that path (another file's is kept); a store directory replaced by a symbolic
link (before the sweep: refused before any work; during it: only the link is
removed), and a lock file replaced by a directory are refused, naming
what is wrong; a chunk copied from another sweep's store (same index and range, its
own valid file) is discarded; ``simulate -o`` and ``boundary -o`` refuse what
``sweep`` refuses; ``boundary`` of a study sweeping v only refuses a picture
before writing; ``export`` of a one-point sweep, ``plot --x v --y v``.
"""
from __future__ import annotations

import os
import signal
import textwrap

import numpy as np
import pytest
import xarray as xr

import sweepcore as sc
from sweepcore.cli import main
from sweepcore.io import DamagedChunkWarning, StoreDamaged, WorkingStore, open_result
from sweepcore.io.netcdf import netcdf_encoding

V = np.array([4.25, 5.5])           # v values whose bytes occur once in a file


def small_grid(v=V):
    return sc.Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0, alpha2=0.01, v=v)


@pytest.fixture(scope="module")
def result(tmp_path_factory):
    path = tmp_path_factory.mktemp("result") / "map.nc"
    sc.sweep(small_grid(), path=path, progress=False).close()
    return path


@pytest.fixture
def no_hang():
    """Fail (instead of blocking the suite) after 20 s."""
    def alarm(*_):
        raise TimeoutError("blocked for 20 s")
    old = signal.signal(signal.SIGALRM, alarm)
    signal.alarm(20)
    yield
    signal.alarm(0)
    signal.signal(signal.SIGALRM, old)


def flip_a_bit_of_v(src, dst):
    data = bytearray(src.read_bytes())
    at = data.find(V.tobytes())
    assert at > 0 and data.find(V.tobytes(), at + 1) < 0, "v's bytes not found once"
    data[at + 9] ^= 0x04           # a bit of the mantissa of v[1]
    dst.write_bytes(bytes(data))


# ------------------------------------------------------------ checksums
def test_a_bit_flipped_in_a_coordinate_fails_its_checksum(result, tmp_path):
    assert open_result(result)["v"].values.tolist() == V.tolist()
    flip_a_bit_of_v(result, tmp_path / "flipped.nc")
    with pytest.raises(ValueError, match=r"flipped\.nc .*cannot be read.*Fletcher-32"):
        open_result(tmp_path / "flipped.nc")


def test_without_checksums_the_same_flip_is_read_back_silently(result, tmp_path):
    """The control: what the checksum prevents."""
    ds = open_result(result)
    enc = {k: {**e, "fletcher32": False} for k, e in netcdf_encoding(ds).items()}
    ds.to_netcdf(tmp_path / "plain.nc", engine="netcdf4", encoding=enc)
    flip_a_bit_of_v(tmp_path / "plain.nc", tmp_path / "flipped.nc")
    with xr.open_dataset(tmp_path / "flipped.nc", engine="netcdf4") as back:
        assert back["v"].values[1] != V[1]


def test_every_array_of_a_result_carries_a_checksum(result):
    import netCDF4
    with netCDF4.Dataset(result) as nc:
        arrays = [v for v in nc.variables.values() if v.ndim > 0]
        assert arrays and all(v.filters()["fletcher32"] for v in arrays)


# ------------------------------------------------------------ open_result and info
def test_open_result_names_what_is_not_a_result(result, tmp_path, no_hang):
    os.mkfifo(tmp_path / "fifo.nc")
    (tmp_path / "cut.nc").write_bytes(result.read_bytes()[:3000])
    (tmp_path / "dir.nc").mkdir()
    with pytest.raises(ValueError, match="path is empty"):
        open_result("")
    with pytest.raises(FileNotFoundError, match="no such result file: .*none.nc"):
        open_result(tmp_path / "none.nc")
    with pytest.raises(ValueError, match=r"fifo\.nc is a FIFO, not a result file"):
        open_result(tmp_path / "fifo.nc")
    with pytest.raises(ValueError, match=r"dir\.nc is a directory, not a result file"):
        open_result(tmp_path / "dir.nc")
    with pytest.raises(ValueError, match=r"cut\.nc \(3,000 bytes\) cannot be read .*"
                                         "truncated"):
        open_result(tmp_path / "cut.nc")


@pytest.mark.parametrize("name, words", [
    ("fifo.nc", "is a FIFO"), ("dir.nc", "is a directory"),
    ("cut.nc", "truncated, damaged")])
def test_info_names_what_is_wrong_with_the_file(result, tmp_path, capsys, no_hang,
                                                name, words):
    os.mkfifo(tmp_path / "fifo.nc")
    (tmp_path / "dir.nc").mkdir()
    (tmp_path / "cut.nc").write_bytes(result.read_bytes()[:3000])
    assert main(["info", str(tmp_path / name)]) == 2
    assert words in capsys.readouterr().err


def test_run_of_a_fifo_study_is_refused_without_blocking(tmp_path, capsys, no_hang):
    os.mkfifo(tmp_path / "s.toml")
    assert main(["run", str(tmp_path / "s.toml")]) == 2
    assert "not a regular file (a FIFO)" in capsys.readouterr().err


# ------------------------------------------------------------ the working store
def test_a_killed_writes_temporary_is_removed_by_the_next_sweep(tmp_path):
    path = tmp_path / "map.nc"
    left = tmp_path / f".map.nc.{'ab' * 16}.tmp"       # temporary_name's pattern
    other = tmp_path / f".other.nc.{'ab' * 16}.tmp"
    left.write_bytes(b"half a file")
    other.write_bytes(b"someone else's")
    sc.sweep(small_grid(), path=path, progress=False).close()
    assert not left.exists() and other.exists() and path.is_file()


def test_a_store_replaced_by_a_symlink_is_refused_before_work(tmp_path):
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    os.symlink(elsewhere, tmp_path / "map.nc.partial")
    with pytest.raises(StoreDamaged, match=r"map\.nc\.partial is a symbolic link"):
        sc.sweep(small_grid(), path=tmp_path / "map.nc", progress=False)
    assert not (tmp_path / "map.nc").exists() and os.listdir(elsewhere) == []


def test_a_store_replaced_by_a_symlink_during_the_sweep_is_unlinked_only(tmp_path):
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    (elsewhere / "keep").write_text("x")
    store = WorkingStore.open(tmp_path / "map.nc", "0" * 64, {}, 2, 3, 1, 1)
    os.rename(store.directory, tmp_path / "moved")
    os.symlink(elsewhere, store.directory)
    with pytest.warns(RuntimeWarning, match="replaced by a symbolic link"):
        store.remove()
    assert not os.path.lexists(store.directory)
    assert (elsewhere / "keep").read_text() == "x"


def test_a_lock_file_replaced_by_a_directory_is_named(tmp_path):
    store = tmp_path / "map.nc.partial"
    WorkingStore.open(tmp_path / "map.nc", "0" * 64, {}, 2, 3, 1, 1).close()
    (store / "lock").unlink()
    (store / "lock").mkdir()
    with pytest.raises(StoreDamaged, match=r"the lock file .*partial/lock of the "
                                           "working store is not a regular file"):
        WorkingStore.open(tmp_path / "map.nc", "0" * 64, {}, 2, 3, 1, 1)


def test_a_chunk_copied_from_a_store_of_other_settings_is_discarded(tmp_path):
    data = np.arange(6.0).reshape(2, 3)
    with WorkingStore.open(tmp_path / "a.nc", "a" * 64, {}, 4, 3, 2, 2) as a:
        a.write(0, data)
    with WorkingStore.open(tmp_path / "b.nc", "b" * 64, {}, 4, 3, 2, 2) as b:
        b.write(1, data)
    (copied,) = (tmp_path / "a.nc.partial").glob("chunk-000000.*.npy")
    os.link(copied, tmp_path / "b.nc.partial" / copied.name)
    with WorkingStore.open(tmp_path / "b.nc", "b" * 64, {}, 4, 3, 2, 2) as b:
        with pytest.warns(DamagedChunkWarning, match="chunk-000000.*copied from a "
                                                     "sweep of other settings"):
            assert b.verified() == [1]
    with WorkingStore.open(tmp_path / "a.nc", "a" * 64, {}, 4, 3, 2, 2) as a:
        assert a.verified() == [0]              # at home it is valid
        np.testing.assert_array_equal(a.read(0), data)


# ------------------------------------------------------------ the command line
def hostile(tmp_path, kind):
    path = tmp_path / "out.nc"
    if kind == "symlink":
        (tmp_path / "target.nc").write_bytes(b"keep")
        os.symlink(tmp_path / "target.nc", path)
    elif kind == "read-only":
        path.write_bytes(b"keep")
        path.chmod(0o444)
    else:
        os.mkfifo(path)
    return path


@pytest.mark.parametrize("kind, words", [("symlink", "is a symbolic link"),
                                         ("read-only", "is a read-only file"),
                                         ("fifo", "is a FIFO")])
def test_simulate_output_refuses_what_sweep_refuses(tmp_path, capsys, no_hang, kind,
                                                    words):
    out = hostile(tmp_path, kind)
    assert main(["simulate", "--m", "5", "--k", "50", "--r-y", "10", "--v", "4",
                 "--t-end", "1", "-o", str(out)]) == 2
    assert words in capsys.readouterr().err
    assert kind == "fifo" or (tmp_path / ("target.nc" if kind == "symlink" else
                                          "out.nc")).read_bytes() == b"keep"


STUDY_V_ONLY = textwrap.dedent("""\
    title = "v only"
    [axes]
    m = 5.0
    k = 50.0
    r_y = 10.0
    alpha1 = 1.0
    alpha2 = 0.01
    v = { start = 4.0, stop = 8.0, num = 5 }
    """)


def test_boundary_output_refuses_what_sweep_refuses(tmp_path, capsys, no_hang):
    (tmp_path / "s.toml").write_text(STUDY_V_ONLY)
    out = hostile(tmp_path, "symlink")
    assert main(["boundary", str(tmp_path / "s.toml"), "-o", str(out)]) == 2
    assert "is a symbolic link" in capsys.readouterr().err
    assert (tmp_path / "target.nc").read_bytes() == b"keep"


def test_boundary_along_another_parameter_writes_its_picture(tmp_path, capsys):
    """A search along alpha2 (v the second axis) wrote its result and no picture
    ("boundary curves are drawn for searches along v"): now the picture, the
    located curves with alpha2 across in its units, and plot draws the file too."""
    (tmp_path / "s.toml").write_text(STUDY_V_ONLY.replace(
        "alpha2 = 0.01\n", "alpha2 = { start = 0.005, stop = 0.02, num = 6 }\n").replace(
        "start = 4.0, stop = 8.0, num = 5", "start = 5.0, stop = 7.0, num = 3")
        + "[boundary]\nalong = \"alpha2\"\nscan = 8\n")
    b, png = tmp_path / "b.nc", tmp_path / "b.png"
    assert main(["boundary", str(tmp_path / "s.toml"), "-o", str(b)]) == 0
    assert "no picture" not in capsys.readouterr().out
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    fig = sc.plot_result(open_result(b))
    ax = fig.axes[0]
    assert ax.get_xlabel().startswith("cubic friction-speed coefficient")
    assert "kN s$^3$/cm$^3$" in ax.get_xlabel()
    drawn = [ln.get_xdata() for ln in ax.lines]
    v_hopf = open_result(b)["v_hopf"].values
    assert np.isfinite(v_hopf).all()
    np.testing.assert_array_equal(drawn[0], v_hopf)


def test_boundary_of_one_swept_axis_refuses_a_picture_before_writing(tmp_path,
                                                                     capsys):
    (tmp_path / "s.toml").write_text(STUDY_V_ONLY)
    b, png = tmp_path / "b.nc", tmp_path / "b.png"
    assert main(["boundary", str(tmp_path / "s.toml"), "-o", str(b), "--png",
                 str(png)]) == 2
    assert "sweeps v only" in capsys.readouterr().err
    assert not b.exists() and not png.exists()
    # without --png: the file, and a word on the picture not drawn
    assert main(["boundary", str(tmp_path / "s.toml"), "-o", str(b)]) == 0
    assert "(no picture: " in capsys.readouterr().out
    v_hopf = float(open_result(b)["v_hopf"])
    assert abs(v_hopf - np.sqrt(1.0 / 0.03)) < 1e-6        # v* = sqrt(alpha1/(3 alpha2))
    assert not png.exists()


def test_export_of_a_one_point_sweep_is_one_row(tmp_path):
    path = tmp_path / "one.nc"
    sc.sweep(small_grid(4.0), path=path, progress=False).close()
    assert main(["export", str(path), "--csv", str(tmp_path / "one.csv")]) == 0
    lines = (tmp_path / "one.csv").read_text().splitlines()
    assert len(lines) == 2
    row = dict(zip(lines[0].split(","), lines[1].split(",")))
    assert float(row["v [cm s-1]"]) == 4.0 and float(row["m [kN s2 cm-1]"]) == 5.0
    assert float(row["amplitude [cm]"]) == float(open_result(path)["amplitude"])


def test_plot_with_the_same_axis_twice_is_refused(tmp_path, capsys):
    path = tmp_path / "two.nc"
    sc.sweep(sc.Grid(m=5.0, k=50.0, r_y=10.0, alpha1=1.0, alpha2=[0.01, 0.02],
                     v=[4.0, 5.0]), path=path, progress=False).close()
    assert main(["plot", str(path), "--x", "v", "--y", "v"]) == 2
    assert "--x and --y are both v" in capsys.readouterr().err
    assert not path.with_suffix(".png").exists()
