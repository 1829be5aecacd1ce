"""Chatter verdicts (robomill.chatter.verdicts) on signals whose truth is planted: a
tooth-passing comb with run-out lines, noise, and a non-harmonic line growing in time."""

import numpy as np
import pytest

from robomill.chatter.verdicts import default_settings, judge, recommended_speeds_rpm

FS_HZ = 10_000.0
RPM, FLUTES = 6000.0, 3  # spindle 100 Hz, tooth passing 300 Hz
CHATTER_HZ = 1234.5  # between the comb's lines 1200 and 1300 Hz


def comb_signal(duration_s=4.0, seed=0, chatter_amp=0.0, noise=0.05):
    rng = np.random.default_rng(seed)
    t = np.arange(int(duration_s * FS_HZ)) / FS_HZ
    x = sum(np.cos(2 * np.pi * 300.0 * k * t + k) / k for k in range(1, 10))  # tooth passing
    x = x + sum(0.05 * np.cos(2 * np.pi * 100.0 * k * t + 2 * k) for k in (1, 2, 4, 5))  # run-out
    if chatter_amp:
        grow = chatter_amp * np.exp(np.log(100.0) * (t / t[-1] - 1.0))  # 40 dB over the record
        x = x + grow * np.sin(2 * np.pi * CHATTER_HZ * t)
    return x + noise * rng.standard_normal(t.size)


@pytest.fixture(scope="module")
def settings():
    return default_settings()


def test_planted_growing_line_is_chatter_at_its_frequency(settings):
    v = judge(comb_signal(chatter_amp=1.0), FS_HZ, settings, spindle_rpm=RPM, flutes=FLUTES)
    assert v.verdict == "chatter"
    assert abs(v.chatter_hz - CHATTER_HZ) < 1.0
    assert v.energy_ratio >= settings.energy_ratio_threshold
    assert v.growth_db_s > 5.0  # planted: 40 dB over 4 s = 10 dB/s
    assert v.comb_source == "design"
    # by hand: 60 * 1234.5 / 3 = 24690 rpm / k; k = 4 gives 6172.5, nearest to 6000
    assert v.speeds_rpm[0] == pytest.approx(6172.5, abs=2.0)
    assert v.speeds_rpm[1] == pytest.approx(24690.0 / 5, abs=2.0)
    assert "1234" in v.evidence and "threshold" in v.evidence


def test_comb_and_noise_is_stable(settings):
    v = judge(comb_signal(), FS_HZ, settings, spindle_rpm=RPM, flutes=FLUTES)
    assert v.verdict == "stable"
    assert np.isnan(v.chatter_hz)
    assert v.energy_ratio < settings.energy_ratio_threshold


def test_comb_estimated_when_no_speed_is_given(settings):
    v = judge(comb_signal(chatter_amp=1.0, seed=3), FS_HZ, settings, flutes=FLUTES)
    assert v.comb_source == "estimated"
    assert v.comb_hz == pytest.approx(300.0, abs=0.5)  # the tooth passing, not a subharmonic
    assert v.verdict == "chatter" and abs(v.chatter_hz - CHATTER_HZ) < 1.0
    assert "estimated" in v.evidence
    s = judge(comb_signal(seed=4), FS_HZ, settings)
    assert s.verdict == "stable" and s.comb_source == "estimated"


def test_no_speed_and_no_comb_is_undetermined(settings):
    rng = np.random.default_rng(1)
    v = judge(rng.standard_normal(int(3 * FS_HZ)), FS_HZ, settings)
    assert v.verdict == "undetermined"
    assert "no spindle speed stated" in v.evidence


def test_short_record_is_undetermined(settings):
    v = judge(np.ones(100), FS_HZ, settings, spindle_rpm=RPM, flutes=FLUTES)
    assert v.verdict == "undetermined" and "shorter" in v.evidence


def test_speeds_in_range_by_hand():
    # f_c = 500 Hz, Z = 2: 15000 / k rpm; in 4000-16000: k = 1..3 -> 15000, 7500, 5000
    assert recommended_speeds_rpm(500.0, 2, (4000.0, 16000.0)) == [15000.0, 7500.0, 5000.0]
    assert recommended_speeds_rpm(500.0, 2, (4000.0, 16000.0), spindle_rpm=7000.0)[0] == 7500.0
    assert recommended_speeds_rpm(500.0, 0, (4000.0, 16000.0)) == []


def test_simulated_cuts_below_and_above_the_lobe(settings):
    """The Shagniev 2019 robot-tool model's closed-loop force (robomill.chatter.timedomain) at 0.85
    and 1.15 of the critical depth that the semi-discretization gives at 1260 rpm (a truth
    independent of the verdict): stable below; chatter above, at an odd multiple of half the
    tooth-passing frequency, because the critical multiplier there is real and negative
    (period doubling, a flip bifurcation)."""
    from robomill.chatter.lobes_sdm import critical_depth
    from robomill.chatter.timedomain import SeedParams, SeedSimulation, horizontal_tool

    p = SeedParams()
    a_b, mu = critical_depth(horizontal_tool(p), p.cutting_model(), p.spindle_rpm,
                             depth_max_m=2e-3, m=60, rtol=1e-3)
    assert mu.real < -0.99 and abs(mu.imag) < 1e-6  # flip
    tooth_hz = p.teeth * p.spindle_rpm / 60.0
    out = {}
    for frac in (0.85, 1.15):
        sim = SeedSimulation(p, frac * a_b, steps_per_tooth=128, duration_s=2.0)
        sim.run(2.0)
        rec = sim.record()
        out[frac] = judge(np.column_stack([rec["Rx_N"], rec["Rz_N"]]), sim.record_fs_hz,
                          settings, spindle_rpm=p.spindle_rpm, flutes=p.teeth)
    assert out[0.85].verdict == "stable"
    v = out[1.15]
    assert v.verdict == "chatter" and v.growth_db_s > 10.0
    half = v.chatter_hz / (tooth_hz / 2.0)
    assert abs(half - round(half)) < 0.05 and round(half) % 2 == 1


def test_the_line_is_a_real_line_not_a_harmonics_skirt(settings):
    """Very strong harmonics (their Hann skirts and side lobes far above the noise) and a weak
    planted line between them: the strongest non-harmonic line is the planted one, and it is
    too weak for chatter."""
    t = np.arange(int(4 * FS_HZ)) / FS_HZ
    x = sum(100.0 * np.cos(2 * np.pi * 300.0 * k * t) / k for k in range(1, 10))
    x = x + 0.5 * np.sin(2 * np.pi * CHATTER_HZ * t)
    x = x + 0.01 * np.random.default_rng(7).standard_normal(t.size)
    v = judge(x, FS_HZ, settings, spindle_rpm=RPM, flutes=FLUTES)
    assert v.line_hz == pytest.approx(CHATTER_HZ, abs=1.0)
    assert v.verdict == "stable" and v.energy_ratio < 1e-3  # (0.5/100)^2 of the first alone


def test_spindle_off_its_command_is_found_not_called_chatter(settings):
    """The spindle turns 2 % faster than the design says (6120 for 6000 rpm): the comb is
    moved onto the signal's harmonics and the cut is stable; with the comb left at the design
    (speed_tolerance 0) its drifted harmonics would pass for chatter."""
    import dataclasses

    t = np.arange(int(4 * FS_HZ)) / FS_HZ
    tooth = 6120.0 * FLUTES / 60.0  # 306 Hz
    x = sum(np.cos(2 * np.pi * tooth * k * t + k) / k for k in range(1, 10))
    x = x + 0.05 * sum(np.cos(2 * np.pi * tooth / 3 * k * t) for k in (1, 2, 4))  # run-out
    x = x + 0.05 * np.random.default_rng(11).standard_normal(t.size)
    v = judge(x, FS_HZ, settings, spindle_rpm=RPM, flutes=FLUTES)
    assert v.verdict == "stable"
    assert v.comb_hz == pytest.approx(tooth, abs=0.3)
    assert "+2.0 %" in v.evidence
    fixed = dataclasses.replace(settings, speed_tolerance=0.0)
    assert judge(x, FS_HZ, fixed, spindle_rpm=RPM, flutes=FLUTES).verdict == "chatter"


def broadband_signal(late_amp, forced_amp=0.0, duration_s=4.0, seed=5):
    """The comb, plus from 3 s on band-limited noise (200–2000 Hz: the force of teeth leaving
    and re-entering the cut, no line in it) of rms ``late_amp``, plus a steady forced line
    at 777 Hz of amplitude ``forced_amp`` (off the comb)."""
    rng = np.random.default_rng(seed)
    x = comb_signal(duration_s=duration_s, seed=seed)
    t = np.arange(x.size) / FS_HZ
    spec = np.fft.rfft(rng.standard_normal(x.size))
    fr = np.fft.rfftfreq(x.size, 1 / FS_HZ)
    spec[(fr < 200.0) | (fr > 2000.0)] = 0.0
    burst = np.fft.irfft(spec, x.size)
    burst *= late_amp / burst.std() * (t >= 3.0)
    return x + burst + forced_amp * np.sin(2 * np.pi * 777.0 * t)


def test_late_broadband_chatter_is_chatter_and_a_forced_line_is_not(settings):
    """Power spread off the comb late in the record (no line stands above its floor, and the
    mean spectrum over the whole record hardly shows it) is chatter; a steady forced line
    carrying a third of the power, or the comb alone, is not."""
    rms_comb = float(np.std(comb_signal()))
    v = judge(broadband_signal(3.0 * rms_comb), FS_HZ, settings, spindle_rpm=RPM,
              flutes=FLUTES)
    assert v.verdict == "chatter"
    assert 200.0 <= v.chatter_hz <= 2000.0
    assert "off the spindle's harmonics" in v.evidence
    assert v.speeds_rpm
    # the same power as a steady forced line: a third of the record's power, stable
    forced = judge(broadband_signal(0.0, forced_amp=rms_comb), FS_HZ, settings,
                   spindle_rpm=RPM, flutes=FLUTES)
    assert forced.verdict == "chatter"  # the line test (step 4) calls the line; the air pass
    assert abs(forced.chatter_hz - 777.0) < 3.0  # tells it forced
    assert "off the spindle's harmonics" not in forced.evidence
    # set aside as forced (judged beside an air pass), the record is stable again
    again = judge(broadband_signal(0.0, forced_amp=rms_comb), FS_HZ, settings,
                  spindle_rpm=RPM, flutes=FLUTES, set_aside_hz=(forced.chatter_hz,))
    assert again.verdict == "stable"
    weak = judge(broadband_signal(0.3 * rms_comb), FS_HZ, settings, spindle_rpm=RPM,
                 flutes=FLUTES)
    assert weak.verdict == "stable"
