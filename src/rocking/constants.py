"""Physical constants shared by every module.

One value of g is used everywhere: to convert records given in g to m/s², in the
equations of motion and in the normalized intensity PGA/(g tan α). Using the same
constant in all three places makes the normalization exact whatever its value.
"""

G: float = 9.80665
"""Standard gravity [m/s²] (the value the PEER record headers are converted with)."""
