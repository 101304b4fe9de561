"""Shared interpreter core: parsing, values, the machine and the compiler to Python source."""
