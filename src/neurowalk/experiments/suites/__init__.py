"""The run suites that figures and studies share: their arenas, run specs, success rules and stored runs.

* :mod:`.deadends`: the dead ends of Fig. 3 and 5 (simple deadlock, narrow passage and its ±20% geometries);
  :mod:`.long_runs`: their long runs in the original arenas, and what the paper's "time steps" are;
  :mod:`.deadends_plot` draws them.
* :mod:`.random_envs`: the random environments of Table 2 and Fig. 6, and their two success rules (not stuck;
  coverage); :mod:`.confinement`: the traps and confined spaces a path met there (Fig. 6's classes);
  :mod:`.random_envs_plot` draws Table 2.
* :mod:`.climbing`: the climbing track of Fig. 10 and the step-height sweep.
* :mod:`.real_robot`: the runs, snapshots and drawings of Fig. 8 and 9 (physics AMOSII).
* :mod:`.timing`: run lengths in seconds of simulated time at a run's control rate, and the comparison of
  simulated event times with the real robot's (Fig. 8-10).
"""
