# `analysis` is the installed package (tools/install-deps.sh); pytest puts this directory on
# the import path for `synth`.
import pytest
import synth


@pytest.fixture(scope="session")
def table():
    return synth.make_table(seed=1)


@pytest.fixture(scope="session")
def report_dir(table, tmp_path_factory):
    """One report build shared by the report and predictor tests (it is slow)."""
    import numpy as np

    from analysis.report.report import build_report
    out = tmp_path_factory.mktemp("report")
    v = np.geomspace(1e-3, 1.0, 10)
    t = np.linspace(0.0, 20.0, 500)
    build_report(table, out, n_boot=30, seed=0,
                 restitution=(v, 1 - 0.3 * v ** 0.2, v, 1 - 0.3 * v ** 0.2),
                 trace=(t, 40 + np.sin(t), 2.0), coordination=synth.pz_table(table),
                 flow=synth.flow_panels())
    return out


def pytest_configure(config):
    config.addinivalue_line("markers", "slow: over about 2 s on an idle 2-core machine; tools/test.sh --quick "
                                       "leaves these out (`-m 'not slow'`), the full suite runs them")
