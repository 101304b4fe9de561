"""Python: the closed form as plain float64 math, used to test the derivation numerically."""
