"""The one verify engine (verify_cell): every kind's programs, the same checks and scenarios, one report."""
