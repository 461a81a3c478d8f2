"""The control loop (episode.py) and what it records (trajectory.py)."""
