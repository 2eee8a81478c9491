"""The report's figures in the paper's order, by name: each one's file name (stable: the report and
the workflow's rules use it), caption, and whether it also writes <name>.md (Table I).

Declared apart from their drawing (figure_list, which imports matplotlib, SciPy and pandas) so
that the workflow plans the figures without those imports: its rules load this module at every
Snakemake start, and under SLURM in every job too (about 1.2 s of CPU each, figure_list's import).
"""
from typing import NamedTuple


class FigureName(NamedTuple):
    name: str
    caption: str
    markdown: bool = False


FIGURES = (
    FigureName("fig02_restitution", "Fig. 2: restitution coefficient"),
    FigureName("fig04_force_trace", "Fig. 4: force trace"),
    FigureName("fig05_drag_vs_Fr_mu0.5", "Fig. 5: drag vs Fr, μ = 0.5"),
    FigureName("fig06_theta_vs_Fr", "Fig. 6: contact angle θ vs Fr (per formation; time-weighted beside)"),
    FigureName("fig07_coordination_distribution", "Fig. 7: distribution of the bulk coordination number"),
    FigureName("fig08_kappa_vs_Fr", "Fig. 8: κ vs Fr"),
    FigureName("fig09_flow_field", "Fig. 9: velocity field around the intruder"),
    FigureName("fig10_drag_vs_Fr_mu0", "Fig. 10: drag vs Fr, μ = 0"),
    FigureName("table1_mu0_regime1", "Table I: μ = 0 regime-I coefficients", markdown=True),
    FigureName("fig11_quasistatic_vs_mu", "Fig. 11: quasistatic drag for small μ, D = 2d"),
    FigureName("fig12_yield_vs_mu", "Fig. 12: yield force vs μ"),
    FigureName("fig13_yield_vs_D", "Fig. 13: yield force vs D*+1, collapse, f(μ)"),
    FigureName("fig14_phi_vs_mu", "Fig. 14: φ_μ vs μ"),
    FigureName("fig15_scaled_drag_vs_Fr_D", "Fig. 15: drag scaled by (D*+1)^φ_μ"),
    FigureName("fig16_drag_vs_Fr_depth", "Fig. 16: drag vs Fr at several depths"),
    FigureName("fig17_yield_vs_h", "Fig. 17: yield force vs h, collapse, g(μ)"),
    FigureName("fig18_alpha_and_sum_rule", "Fig. 18: α_μ (drag at speed, averaged; and from F_Y) and the sum rule"),
    FigureName("fig19_scaled_drag_vs_Fr_h", "Fig. 19: drag scaled by h^α_μ"),
    FigureName("fig20_kn_gamman", "Fig. 20: K_n and γ_n variations"),
)
BY_NAME = {f.name: f for f in FIGURES}
NAMES = [f.name for f in FIGURES]
