"""``neurowalk baseline``: learned policies against the networks (:mod:`.comparison`): an evolved recurrent network
(:mod:`.evolved_rnn`, CMA-ES) and PPO / recurrent PPO (:mod:`.ppo`, the ``rl`` extra)."""
