"""Domino chain scenarios: build, push, record events, measure the wave (paper section 3).

A researcher's script needs only this package's names::

    from dominowave.chain import ChainParams, DominoChain, Push

    chain = DominoChain(ChainParams(n_dominoes=30, d_over_l=0.4))
    run = chain.run(Push(omega=10.0))          # one DEM run
    ens = chain.ensemble(None, members=8)      # perturbed pushes: speed +- error
"""

from dominowave.chain.build import ChainParams, DominoShape, chain_positions, domino_shape
from dominowave.chain.compare import (
    EffectiveDomino,
    effective_domino,
    theory_collision_time,
    theory_first_contacts,
    theory_speed,
)
from dominowave.chain.events import ChainRecord, DominoEvents, analyse_events
from dominowave.chain.scenario import ChainEnsemble, ChainRun, DominoChain, Push
from dominowave.chain.stepper import ChainStepper
from dominowave.chain.wave import (
    EnsembleStats,
    SecondaryWave,
    SteadySpeed,
    ensemble_stats,
    fit_speed,
    local_speeds,
    secondary_wave,
    steady_speed,
    unsettled_reason,
)

__all__ = [
    "ChainEnsemble",
    "ChainParams",
    "ChainRecord",
    "ChainRun",
    "ChainStepper",
    "DominoChain",
    "DominoEvents",
    "DominoShape",
    "EffectiveDomino",
    "EnsembleStats",
    "Push",
    "SecondaryWave",
    "SteadySpeed",
    "analyse_events",
    "chain_positions",
    "domino_shape",
    "effective_domino",
    "ensemble_stats",
    "fit_speed",
    "local_speeds",
    "secondary_wave",
    "steady_speed",
    "theory_collision_time",
    "theory_first_contacts",
    "theory_speed",
    "unsettled_reason",
]
