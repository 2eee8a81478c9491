"""analysis.core.restitution: the Kuwabara-Kono/Brilliantov e(v_n) series of Fig. 2."""
import numpy as np
import pytest

from analysis.core.physics import PAPER_GAMMAN, PAPER_KN, PAPER_RATIO, gamman_for
from analysis.core.restitution import beta, contact_law, kuwabara_kono


def test_series_matches_the_integrated_contact_law_where_it_converges():
    # Four terms: within 1e-4 up to v_n = 0.1, 1e-3 up to 1 and 0.5 % at 10 (truncation).
    for v_max, tol in ((0.1, 1e-4), (1.0, 1e-3), (10.0, 5e-3)):
        v = np.geomspace(0.01, v_max, 4)
        exact = contact_law(v, PAPER_KN, PAPER_GAMMAN)
        assert np.allclose(kuwabara_kono(v, PAPER_KN, PAPER_GAMMAN), exact, rtol=0, atol=tol)


def test_leading_coefficient_for_weak_damping():
    # 1 - e = C1 beta v^(1/5) + O(beta^2): C1 = 1.15344 (Schwager & Poeschel 1998)
    kn, gn, v = 2e8, 50.0, 1.0
    e = contact_law([v], kn, gn)[0]
    assert (1 - e) / (beta(kn, gn) * v ** 0.2) == pytest.approx(1.15344, rel=1e-3)


def test_curve_depends_only_on_gamman_over_kn_to_the_0_6():
    v = np.array([0.01, 0.3, 5.0])
    for kn in (2e4, 2e6):
        assert np.allclose(contact_law(v, kn, gamman_for(kn, PAPER_RATIO)),
                           contact_law(v, PAPER_KN, PAPER_GAMMAN), rtol=1e-6)
        assert np.allclose(kuwabara_kono(v, kn, gamman_for(kn, PAPER_RATIO)),
                           kuwabara_kono(v, PAPER_KN, PAPER_GAMMAN), rtol=1e-12)


def test_impact_speed_must_be_positive():
    with pytest.raises(ValueError, match="impact speed"):
        contact_law([0.0], PAPER_KN, PAPER_GAMMAN)
