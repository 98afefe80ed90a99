"""What kincalc says about a robot, above the engine: the FK and Jacobian reports
(:mod:`~kincalc.analysis.reports`), the result documents (:mod:`~kincalc.analysis.results`)
and the sentences of answers (:mod:`~kincalc.analysis.words`), IK requests in the user's
units (:mod:`~kincalc.analysis.requests`), reachability
(:mod:`~kincalc.analysis.reach`), the workspace (:mod:`~kincalc.analysis.workspace`),
whether two robot descriptions are the same robot (:mod:`~kincalc.analysis.compare`),
formulas (:mod:`~kincalc.analysis.symbolic`, sympy) and pictures
(:mod:`~kincalc.analysis.plot`, matplotlib).
"""

__all__ = ["fk_report", "jacobian_report", "joint_vector"]


def __getattr__(name):
    # lazy: importing one room of the package (words, results) does not load the others
    if name in __all__:
        from . import reports
        return getattr(reports, name)
    raise AttributeError(f"module 'kincalc.analysis' has no attribute {name!r}")
