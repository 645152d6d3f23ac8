"""Referees: impact models integrated from Newton–Euler's laws, sharing no code with the paths they check."""
