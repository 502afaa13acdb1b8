"""Rigid-block limit analysis of running-bond walls by linear programming."""
