"""One stylus profile's form, waviness and roughness (thesis §2.3): detrending, the ISO 16610-21
Gaussian profile filter (zero-order end correction, ISO 16610-28) and the ISO 4287 amplitude
parameters Wt, Wq, Rq, Ra, Rz.
"""

from __future__ import annotations

import numpy as np
import scipy.signal

ALPHA = float(np.sqrt(np.log(2.0) / np.pi))
"""ISO 16610-21 constant α = sqrt(ln 2 / π) (50 % transmission at the cut-off)."""

def detrend_profile(z_um: np.ndarray, x_mm: np.ndarray | None = None
                    ) -> tuple[np.ndarray, float, float]:
    """Remove the least-squares line (stylus tilt) from a profile.

    Returns the detrended profile, the slope [µm/mm] and the offset [µm] removed (thesis
    §2.3: the measured profile is tilted with respect to the stylus path).
    """
    z = np.asarray(z_um, float)
    x = np.arange(z.size, dtype=float) if x_mm is None else np.asarray(x_mm, float)
    slope, offset = np.polyfit(x, z, 1)
    return z - (slope * x + offset), float(slope), float(offset)


def gaussian_weights(lambda_c_mm: float, dx_mm: float, half_width_cutoffs: float = 1.0
                     ) -> np.ndarray:
    """Sampled ISO 16610-21 weighting function, normalized to unit sum.

    .. math:: s(x) = \\frac{1}{α λ_c} \\exp\\left[-π \\left(\\frac{x}{α λ_c}\\right)^2\\right],
              \\quad α = \\sqrt{\\ln 2 / π}

    truncated at ``± half_width_cutoffs · λc`` (at ±λc the weight is 7e-7 of its peak).
    """
    n_half = int(np.ceil(half_width_cutoffs * lambda_c_mm / dx_mm))
    x = np.arange(-n_half, n_half + 1) * dx_mm
    s = np.exp(-np.pi * (x / (ALPHA * lambda_c_mm)) ** 2)
    return s / s.sum()


def gaussian_filter(z_um: np.ndarray, dx_mm: float, lambda_c_mm: float, *,
                    end: str = "renormalize", half_width_cutoffs: float = 1.0) -> np.ndarray:
    """ISO 16610-21 Gaussian mean line (the waviness profile) of ``z_um``.

    The amplitude transmission of the mean line is ``exp(−π (α λc / λ)²)``: 50 % at
    ``λ = λc``, → 1 for long waves. The roughness profile is ``z − mean line``.

    Parameters
    ----------
    end
        ``"renormalize"`` (default): near the ends the weights are renormalized over the part
        of the kernel that lies inside the profile (zero-order end correction, ISO 16610-28),
        so no sample is lost and a constant or slowly varying profile is passed unchanged up
        to the ends. ``"zero"``: the profile is zero-padded (the plain convolution; the mean
        line falls off within λc of each end).

    Examples
    --------
    >>> dx = 0.00125; x = np.arange(12000) * dx
    >>> w = gaussian_filter(np.sin(2 * np.pi * x / 0.25), dx, 0.25)
    >>> round(float(np.abs(w[4000:8000]).max()), 3)
    0.5
    """
    z = np.asarray(z_um, float)
    s = gaussian_weights(lambda_c_mm, dx_mm, half_width_cutoffs)
    if s.size > 2 * z.size:
        raise ValueError(f"profile of {z.size} samples is shorter than the filter kernel "
                         f"({s.size} samples for λc = {lambda_c_mm} mm)")
    num = scipy.signal.oaconvolve(z, s, mode="same")
    if end == "zero":
        return num
    if end != "renormalize":
        raise ValueError(f"end={end!r}: expected 'renormalize' or 'zero'")
    den = scipy.signal.oaconvolve(np.ones_like(z), s, mode="same")
    return num / den


def split_profile(z_um: np.ndarray, dx_mm: float, lambda_c_mm: float, **kw
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Waviness (Gaussian mean line) and roughness (the rest) of a detrended profile."""
    w = gaussian_filter(z_um, dx_mm, lambda_c_mm, **kw)
    return w, np.asarray(z_um, float) - w


def rz_um(r_um: np.ndarray, n_sampling: int) -> float:
    """Rz (ISO 4287): highest peak + deepest valley in each sampling length of
    ``n_sampling`` samples (λc), averaged over all complete sampling lengths."""
    r = np.asarray(r_um, float)
    m = r.size // n_sampling
    if m < 1:
        return float(r.max() - r.min())
    segs = r[: m * n_sampling].reshape(m, n_sampling)
    segs = segs - segs.mean(axis=1, keepdims=True)
    return float(np.mean(segs.max(axis=1) - segs.min(axis=1)))


def amplitude_parameters(waviness_um: np.ndarray, roughness_um: np.ndarray, dx_mm: float,
                         lambda_c_mm: float) -> dict[str, float]:
    """Wt (peak to valley), Wq (RMS) of the waviness; Rq (RMS), Ra (mean absolute), Rz of the
    roughness (ISO 4287, evaluation length = the whole profile) [µm]."""
    w = np.asarray(waviness_um, float) - np.mean(waviness_um)
    r = np.asarray(roughness_um, float) - np.mean(roughness_um)
    return {
        "Wt_um": float(w.max() - w.min()),
        "Wq_um": float(np.sqrt(np.mean(w**2))),
        "Rq_um": float(np.sqrt(np.mean(r**2))),
        "Ra_um": float(np.mean(np.abs(r))),
        "Rz_um": rz_um(r, max(int(round(lambda_c_mm / dx_mm)), 2)),
    }
