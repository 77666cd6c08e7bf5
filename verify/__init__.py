"""Verification beyond the bit-exact tests (issue 29): `verify.mutants` (make mutants), planted
single bugs in rtl/ and the tests that catch them. Imports model, hdlbuild and sim; imported by
nothing (tests/test_layers.py)."""
