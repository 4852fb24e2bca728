"""Issue 9 (reliability sweep): each reproducer of the issue, fixed at its root.

Every test here failed on main before the fix (the issue's numbers are quoted
in the comments); the property-based sweeps are in tests/test_properties.py
and the pickling tests in tests/test_pickling.py.
"""

import warnings

import numpy as np
import pandas as pd
import pytest

import supercoil as sc
from supercoil.exceptions import DataError, NoEquilibriumError, ValidityError, ValidityWarning
from supercoil.rod.design import sinusoidal_pitch
from supercoil.tables import row_lines

u = sc.ureg


@pytest.fixture(scope="module")
def dna():
    return sc.load_parameters("dna")


@pytest.fixture(scope="module")
def rod():
    return sc.load_parameters("silicone_rubber_rod")


def messages(record):
    return [str(w.message) for w in record if issubclass(w.category, ValidityWarning)]


def validity_messages(call):
    """(result, ValidityWarning messages) of ``call()``; other warnings stay errors."""
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always", ValidityWarning)
        out = call()
    others = [w for w in rec if not issubclass(w.category, ValidityWarning)]
    assert not others, [str(w.message) for w in others]
    return out, messages(rec)


# ---- item 1: a list of angle or turn quantities means what the array quantity means ----

def test_hat_curve_list_of_turn_quantities_is_not_multiplied_by_two_pi(dna):
    listed = sc.hat_curve(dna, 1.2 * u.pN, [1 * u.turn, 2 * u.turn])
    array = sc.hat_curve(dna, 1.2 * u.pN, [1, 2] * u.turn)
    assert listed["turns"].tolist() == [1.0, 2.0]  # main: 6.28, 12.57
    pd.testing.assert_frame_equal(listed, array)


def test_list_of_radian_quantities_counts_turns(dna):
    t = sc.hat_curve(dna, 1.2 * u.pN, [2 * np.pi * u.rad, 360 * u.deg])["turns"]
    np.testing.assert_allclose(t, [1.0, 1.0], rtol=1e-15)


def test_smooth_helix_list_of_turns(rod):
    h = sc.smooth_helix(rod, [40 * u.turn], 10 * u.cm)
    assert h.turns.m.tolist() == [40.0]  # main: 251 turns
    np.testing.assert_array_equal(h.alpha.m, sc.smooth_helix(rod, [40] * u.turn, 10 * u.cm).alpha.m)


def test_twist_spinning_list_of_turns(rod):
    a = sc.twist_spinning(rod, [40 * u.turn, 50 * u.turn], 0.1 * u.N)
    b = sc.twist_spinning(rod, np.array([40.0, 50.0]), 0.1 * u.N)
    assert a.turns.m.tolist() == [40.0, 50.0]
    np.testing.assert_array_equal(a.pitch.m, b.pitch.m)


def test_a_list_mixing_quantities_and_numbers_is_refused(dna):
    with pytest.raises(TypeError, match=r"'turns' mixes quantities and plain numbers"):
        sc.hat_curve(dna, 1.2 * u.pN, [1 * u.turn, 2])
    with pytest.raises(sc.units.DimensionalityError, match=r"'force'.*incompatible"):
        sc.hat_curve(dna, [1 * u.pN, 1 * u.nm], [0])


# ---- item 3: z > L and zeta outside (0, 1] are never silent ----

def test_extension_longer_than_contour_warns(dna):
    with pytest.warns(ValidityWarning, match=r"extension 25\.69.* outside \[0, L = 20 nm\]"):
        z = sc.hat_curve(dna.replace(length=20 * u.nm), 0.4 * u.pN, [0])["extension"]
    assert z.iloc[0] > 20  # the number is returned, flagged


def test_z_above_L_warns_even_when_the_tail_is_flagged_short(dna):
    short = dna.replace(length=20 * u.nm)
    with pytest.warns(ValidityWarning, match=r"outside"):
        df = sc.hat_curve(short, 0.4 * u.pN, [0], short_tail_length=1 * u.um)
    assert bool(df["short_tail"].iloc[0])


# ---- item 5: a column named twice is a DataError ----

@pytest.mark.parametrize("header", ["force [pN],turns,extension [um],force [pN]",
                                    "force [pN],turns,extension [um],force [N]",
                                    "force,turns,turns [turn]"])
def test_duplicated_csv_column_is_a_data_error(tmp_path, header):
    p = tmp_path / "dup.csv"
    p.write_text("# a: 1\n" + header + "\n1,2,3,4\n")
    with pytest.raises(DataError, match=r"line 2: column '(force|turns)' appears twice"):
        sc.read_csv(p)
    with pytest.raises(DataError, match=r"appears twice"):
        sc.read_tweezers_csv(p)


@pytest.mark.parametrize("reader", [sc.read_csv, sc.read_tweezers_csv])
def test_readers_name_a_bad_path(reader, tmp_path):
    with pytest.raises(TypeError, match=r"path must be a str or a path, got NoneType"):
        reader(None)
    with pytest.raises(DataError, match=r"cannot read"):
        reader(tmp_path)  # a directory
    with pytest.raises(DataError, match=r"no such file"):
        reader(tmp_path / "missing.csv")


# ---- item 6: boolean flags are checked by one helper ----

def test_drop_incomplete_rejects_strings(tmp_path):
    p = tmp_path / "inc.csv"
    p.write_text("force [pN],turns,extension [um]\n1,2,0.3\n1,3,\n")
    with pytest.raises(TypeError, match=r"drop_incomplete must be True or False, got 'False'"):
        sc.read_tweezers_csv(p, drop_incomplete="False")
    with pytest.raises(DataError, match=r"line 3, column 'extension': missing"):
        sc.read_tweezers_csv(p, drop_incomplete=np.False_)


@pytest.mark.parametrize("flag", ["no", "False", 0, 1, None])
def test_thermal_flag_rejects_non_booleans(dna, flag):
    for call in (lambda: sc.hat_curve(dna, 1 * u.pN, [0], thermal=flag),
                 lambda: sc.buckling_turns(dna, 1 * u.pN, thermal=flag),
                 lambda: sc.post_buckling_slope(dna, 1 * u.pN, thermal=flag)):
        with pytest.raises(TypeError, match=r"thermal must be True or False"):
            call()


@pytest.mark.parametrize("register", [sc.register_model, sc.register_interaction])
def test_registry_replace_flag_is_checked(register):
    with pytest.raises(TypeError, match=r"replace must be True or False, got 'yes'"):
        register(object, replace="yes")


# ---- item 7: every DNA function gives the shared validity warnings ----

def test_buckling_turns_warns_overstretching_and_hard_core(dna):
    nb, msgs = validity_messages(lambda: sc.buckling_turns(dna, 1e4 * u.pN))
    text = " ".join(msgs)  # the issue: 7819 turns, silently
    assert "above 65 pN" in text and "< r0" in text
    assert np.isfinite(nb.m).all()


def test_post_buckling_slope_fails_named_at_huge_force(dna):
    with pytest.raises(ValidityError, match=r"10000 pN"), warnings.catch_warnings():
        warnings.simplefilter("ignore", ValidityWarning)
        sc.post_buckling_slope(dna, 1e4 * u.pN)


def test_post_buckling_slope_warns_overstretching(dna):
    _, msgs = validity_messages(lambda: sc.post_buckling_slope(dna, 70 * u.pN, thermal=False))
    assert any("above 65 pN" in m for m in msgs) and any("< r0" in m for m in msgs)


@pytest.mark.parametrize("force", [30.0, 35.0, 43.0])
def test_hat_curve_warns_r_below_r0_between_30_and_44_pN(dna, force):
    _, msgs = validity_messages(lambda: sc.hat_curve(dna, force * u.pN, [0, 50, 100]))
    assert any("< r0" in m for m in msgs)
    # the same limit as the equilibrium itself
    eq, msgs = validity_messages(lambda: sc.plectoneme_equilibrium(dna, force * u.pN))
    assert any("< r0" in m for m in msgs) and eq.radius.m_as("nm") < 1.75


def test_no_r0_warning_below_the_limit(dna):
    with warnings.catch_warnings():
        warnings.simplefilter("error", ValidityWarning)
        sc.hat_curve(dna, 20 * u.pN, [0, 50, 100])
        sc.buckling_turns(dna, 20 * u.pN)


def test_athermal_tail_above_euler_torque_warns(dna):
    df, msgs = validity_messages(
        lambda: sc.hat_curve(dna, 50 * u.pN, np.linspace(0, 150, 7), thermal=False))
    assert any("Euler" in m for m in msgs), msgs
    # independent check of the condition: the tail (stretched or beside a
    # plectoneme) carries |M| > 2 sqrt(B F)
    B, F = dna.si.bending_rigidity, 50e-12
    tail = df[df["phase"] != "fully coiled"]
    assert (np.abs(tail["torque"]) > 2 * np.sqrt(B * F) * 1e21).any()
    _, msgs = validity_messages(lambda: sc.hat_curve(dna, 20 * u.pN, [0, 50], thermal=False))
    assert not any("Euler" in m for m in msgs)


# ---- item 9: unnamed crashes become named errors ----

def test_rod_none_is_named(rod):
    for call in (lambda: sc.smooth_helix(None, 40, 10 * u.cm),
                 lambda: sc.twist_spinning(None, 40, 0.1 * u.N),
                 lambda: sc.design_twist_schedule(None, sinusoidal_pitch(
                     16 * u.mm, 4 * u.mm, 2 * np.pi / (160 * u.mm)))):
        with pytest.raises(TypeError, match=r"rod must be a supercoil.ElasticRod, got NoneType"):
            call()


def test_material_of_the_other_kind_is_named(dna, rod):
    with pytest.raises(TypeError, match=r"dna must be a supercoil.DNA, got ElasticRod"):
        sc.plectoneme_equilibrium(rod, 1.2 * u.pN)
    with pytest.raises(TypeError, match=r"dna must be a supercoil.DNA, got ElasticRod"):
        sc.hat_curve(rod, 1.2 * u.pN, [0])
    with pytest.raises(TypeError, match=r"rod must be a supercoil.ElasticRod, got DNA"):
        sc.smooth_helix(dna, 40, 10 * u.cm)
    with pytest.raises(TypeError, match=r"load_parameters\('dna'\)"):
        sc.hat_curve("dna", 1.2 * u.pN, [0])


def test_shape_mismatch_names_the_arguments(rod):
    with pytest.raises(ValueError, match=r"turns, slack do not broadcast.*\(2,\).*\(3,\)"):
        sc.smooth_helix(rod, [40, 30], [1, 2, 3] * u.cm)
    with pytest.raises(ValueError, match=r"turns, head_tension do not broadcast"):
        sc.twist_spinning(rod, [40, 30], [0.1, 0.2, 0.3] * u.N)


@pytest.mark.parametrize("call", [
    lambda d: sc.extension_factor(d, [1, 2] * u.pN, [1, 2, 3] * u.pN * u.nm, 500 * u.nm),
    lambda d: sc.geometry.curvature([0.1, 0.2] * u.rad, [1, 2, 3] * u.mm),
    lambda d: sc.geometry.tilt_angle([1, 2] * u.mm, [1, 2, 3] * u.mm),
    lambda d: sc.geometry.writhe([0.1, 0.2] * u.rad, 1 * u.mm, [1, 2, 3] * u.mm),
    lambda d: sc.geometry.linking_number([0.1, 0.2] * u.rad, 1 * u.mm, [1, 2, 3] * u.mm,
                                         1 * u.m, 1 / u.m),
])
def test_shape_mismatch_names_the_arguments_everywhere(dna, call):
    with pytest.raises(ValueError, match=r"the shapes of .* do not broadcast together"):
        call(dna)  # main: "operands could not be broadcast together with shapes (2,) (3,)"


def test_tiny_temperature_is_named(dna):
    with pytest.raises(ValueError, match=r"kT.*check temperature"):
        dna.replace(temperature=1e-300 * u.K)  # main: ZeroDivisionError in the solver
    with pytest.raises(ValueError, match=r"bending rigidity A kT"):
        dna.replace(temperature=1e-280 * u.K)


def test_tiny_but_normal_temperature_has_no_equilibrium_named(dna):
    with pytest.raises(NoEquilibriumError, match=r"1.2 pN"):
        sc.plectoneme_equilibrium(dna.replace(temperature=1e-20 * u.K), 1.2 * u.pN)


@pytest.mark.parametrize("change, message", [
    ({"length": 0.1 * u.nm}, r"contour length \(nm\) is 0.1, below its limit 0.34"),
    ({"temperature": 2e4 * u.K}, r"temperature \(K\) is 20000, above its limit 10000"),
])
def test_dna_outside_the_models_limits_is_named_by_every_public_function(dna, change, message):
    """check_dna's limits (one base pair; far above melting), also past its fast path."""
    bad = dna.replace(**change)
    with pytest.raises(ValidityError, match=message):
        sc.plectoneme_equilibrium(bad, 1.2 * u.pN)
    with pytest.raises(ValidityError, match=message):
        sc.hat_curve(bad, 1.2 * u.pN, [0.0, 1.0])
    with pytest.warns(ValidityWarning, match="outside"):  # at the limit: no error
        assert sc.hat_curve(dna.replace(length=0.34 * u.nm), 1.2 * u.pN, [0.0]).shape[0] == 1


@pytest.mark.parametrize("radius", [1e300, 1e-100])
def test_rod_rigidity_out_of_float_range_is_named(rod, radius):
    with pytest.raises(ValueError, match=r"bending rigidity E pi r\^4/4.*check radius"):
        rod.replace(radius=radius * u.m)  # main: OverflowError


@pytest.mark.parametrize("arg", [None, 3, 1.5])
def test_load_parameters_wrong_type(arg):
    with pytest.raises(TypeError, match=r"name_or_path must be a parameter-set name"):
        sc.load_parameters(arg)


def test_complex_inputs_are_named(dna, rod):
    with pytest.raises(TypeError, match=r"'force' is complex"):
        sc.hat_curve(dna, (1 + 1j) * u.pN, [0])
    with pytest.raises(TypeError, match=r"'turns' is complex"):
        sc.hat_curve(dna, 1 * u.pN, np.array([1 + 1j]))  # main: imaginary part dropped
    with pytest.raises(TypeError, match=r"'slack' is complex"):
        sc.smooth_helix(rod, 40, (1 + 2j) * u.cm)
    with pytest.raises(TypeError, match=r"'DNA.length' is complex"):
        dna.replace(length=(1 + 1j) * u.um)


# ---- item 10: no silent non-finite output ----

@pytest.mark.parametrize("model", ["li-zhao", "free-energy", "marko2007"])
@pytest.mark.parametrize("turns", [[np.nan], [0, np.inf], [-np.inf]])
def test_non_finite_turns_are_refused_by_every_model(dna, model, turns):
    with pytest.raises(ValueError, match=r"turns must be finite"):
        sc.hat_curve(dna, 1 * u.pN, turns, model=model)  # marko2007 on main: silent NaN
    with pytest.raises(ValueError, match=r"turns must be finite"):
        sc.free_energy(dna, 1 * u.pN, turns, thermal=False, model=model)


@pytest.mark.parametrize("model", ["li-zhao", "free-energy", "marko2007"])
def test_more_turns_than_helical_turns_is_a_validity_error(dna, model):
    lk0 = dna.si.length / 3.57e-9  # 210 turns for 750 nm
    validity_messages(lambda: sc.hat_curve(dna, 1 * u.pN, [0.99 * lk0], thermal=False,
                                           model=model))  # allowed (maybe flagged)
    with pytest.raises(ValidityError, match=r"Lk0 = L/h = 210\.08"):
        sc.hat_curve(dna, 1 * u.pN, [1.01 * lk0], model=model)
    with pytest.raises(ValidityError, match=r"sigma"):
        sc.hat_curve(dna, 1 * u.pN, [-1e300], model=model)  # main: overflow / inf force


@pytest.mark.parametrize("model", ["li-zhao", "free-energy", "marko2007"])
@pytest.mark.parametrize("force", [0.0, -1.0, 1e-300 * -1])
def test_non_positive_force_is_refused_by_every_model(dna, model, force):
    # one shared check (validity.checked_forces): a toy model without its own check
    # gave raw "invalid value in sqrt" warnings and NaN for negative forces
    for call in (lambda: sc.hat_curve(dna, force * u.pN, [0, 5], model=model),
                 lambda: sc.buckling_turns(dna, force * u.pN, model=model)):
        with pytest.raises(NoEquilibriumError, match=r"force must be positive"):
            call()


def test_empty_turns_give_an_empty_table(dna):
    # it once raised numpy's reduction error; now an empty table, as in 0.1
    t = sc.hat_curve(dna, 1 * u.pN, [], model="marko2007")
    assert len(t) == 0 and "extension" in t.columns


def test_curvature_error_at_a_huge_slope_is_finite_and_exact():
    e = sc.geometry.curvature_error(1e200)  # main: inf
    assert e.m == pytest.approx(1e200 / (2 * np.pi), rel=1e-15)
    assert sc.geometry.curvature_error(0.3).m == pytest.approx(
        np.sqrt(1 + 0.09 / (4 * np.pi**2)), rel=1e-15, abs=0)


def test_geometry_overflow_is_a_named_error():
    with pytest.raises(ValidityError, match=r"pitch is inf for alpha"):
        sc.geometry.pitch_from_tilt(1e-320 * u.rad, 1 * u.m)
    with pytest.raises(ValidityError, match=r"curvature is inf"):
        sc.geometry.curvature(1 * u.rad, 1e-320 * u.m)


# ---- item 12: large inputs in bounded memory ----

@pytest.mark.parametrize("block", [7, 64, 1 << 22])
def test_loader_row_lines_match_the_record_by_record_reading(tmp_path, monkeypatch, block):
    from supercoil import _csvfile

    monkeypatch.setattr(_csvfile, "BLOCK_BYTES", block)  # lines across block borders
    p = tmp_path / "x.csv"
    p.write_bytes(b'\xef\xbb\xbf# a: 1\n#note\n\nforce [pN],turns,extension [um]\n1,0,0.3\n\n'
                  b'   \n2,1,0.4\r\n3,2,0.5\n 4,3,0.6\n\t\n5,4,0.7')
    with _csvfile.CsvFile(p) as src:
        assert src.header_line == 4 and src.provenance == {"a": 1, "comments": ["note"]}
        fast = src.data_lines(5)
        slow = src._data_lines_csv(5)
    assert fast.tolist() == slow.tolist() == [5, 8, 9, 10, 12]
    df = sc.read_tweezers_csv(p)
    assert row_lines(df).tolist() == [5, 8, 9, 10, 12]
    assert df["turns"].tolist() == [0, 1, 2, 3, 4]


def test_loader_row_lines_without_blank_lines_or_final_newline(tmp_path):
    p = tmp_path / "plain.csv"
    p.write_text("# x: 2\n\nforce [pN],turns,extension [um]\n1,0,0.3\n2,1,0.4")
    df = sc.read_tweezers_csv(p)
    assert row_lines(df).tolist() == [4, 5] and df.attrs["provenance"]["x"] == 2


def test_loader_quoted_fields_fall_back_to_csv(tmp_path):
    p = tmp_path / "q.csv"
    p.write_text('molecule,force [pN],turns,extension [um]\n"a\nb",1,0,0.3\nc,1,1,0.3\n')
    df = sc.read_tweezers_csv(p)
    assert row_lines(df).tolist() == [2, 4]


def test_loader_not_utf8_names_the_line(tmp_path):
    p = tmp_path / "bad.csv"
    p.write_bytes(b"# ok: 1\nforce [pN],turns,extension [um]\n1,0,0.3\n1,\xff,0.3\n")
    with pytest.raises(DataError, match="line 4: not UTF-8"):
        sc.read_tweezers_csv(p)
    p.write_bytes(b"# \xff\nforce [pN],turns,extension [um]\n1,0,0.3\n")
    with pytest.raises(DataError, match="line 1: not UTF-8"):
        sc.read_csv(p)


def test_loader_memory_beyond_the_table_is_bounded(tmp_path, monkeypatch):
    import tracemalloc

    from supercoil import _csvfile
    from supercoil.benchmark.memory import write_rotation_csv

    n = 100_000  # ~2.7 MB; the line scan in blocks of 64 kB (1 MB by default)
    monkeypatch.setattr(_csvfile, "BLOCK_BYTES", 1 << 16)
    p = write_rotation_csv(tmp_path / "big.csv", n)
    tracemalloc.start()
    try:
        base, _ = tracemalloc.get_traced_memory()
        df = sc.read_tweezers_csv(p)
        kept, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert len(df) == n and row_lines(df)[-1] == n + 2
    # main: the whole text twice, per-row Python lists and a copy of the frame
    assert (peak - kept) / n <= 64, ((peak - base) / n, (kept - base) / n)


def test_plectoneme_blocks_agree_with_one_block(dna, monkeypatch):
    from supercoil.core.dna import plectoneme as kernel

    f = np.linspace(0.2, 20, 300) * u.pN
    whole = sc.plectoneme_equilibrium(dna, f)
    monkeypatch.setattr(kernel, "BLOCK", 64)  # 300 forces in 5 blocks
    blocks = sc.plectoneme_equilibrium(dna, f)
    for a, b in zip(whole, blocks, strict=True):
        np.testing.assert_allclose(a.m, b.m, rtol=1e-12)


def test_plectoneme_peak_memory_is_bounded(dna, monkeypatch):
    from supercoil.benchmark.memory import plectoneme_memory
    from supercoil.core.dna import plectoneme as kernel

    monkeypatch.setattr(kernel, "BLOCK", 4096)
    m = plectoneme_memory(100_000)  # main: ~277 bytes per force beyond the output
    assert m["bytes_per_force"] <= 64


def test_memory_benchmark_table():
    from supercoil.benchmark import memory

    table = memory.run(sizes=(5000,), log=lambda *a: None)
    assert table.attrs["units"]["bytes_per_force"] == "B"
    row = table.iloc[0]
    assert row["elements"] == 5000 and row["loader_s"] > 0 and row["pandas_s"] > 0
    assert np.isfinite(row["bytes_per_force"])


def test_a_model_giving_nan_is_caught_by_the_shared_layer(dna):
    from supercoil.dna.models import Buckling, DNAModel, HatPoints

    class Broken(DNAModel):  # not registered: passed as an instance
        name = "broken-test-model"
        summary = "returns NaN past 3 turns, never buckles"
        uses_interaction = False

        def _buckling(self, force, dna, thermal, interaction):
            inf = np.full(np.shape(force), np.inf)  # never buckles: allowed
            return Buckling(inf, inf, np.zeros(np.shape(force)))

        def _points(self, turns, force, dna, thermal, interaction, short_tail_length):
            z = np.where(np.abs(turns) > 3, np.nan, dna.length)
            zeros = np.zeros(np.shape(turns))
            return HatPoints(z, zeros, zeros, zeros.astype(np.int8), zeros.astype(bool),
                             z / dna.length)

    model = Broken()
    assert np.isinf(sc.buckling_turns(dna, 1 * u.pN, model=model).m).all()
    sc.hat_curve(dna, 1 * u.pN, [0, 3], model=model)
    with pytest.raises(ValidityError, match=r"'broken-test-model' gives extension = .*nan.* "
                                            r"at force 1 pN, turns 4"):
        sc.hat_curve(dna, 1 * u.pN, [0, 4], model=model)
