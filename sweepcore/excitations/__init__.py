"""Harmonic excitation of the slider: a load on it and motion of its anchor.

``sweepcore.excitations.theory`` holds the closed forms (numpy only).
"""
