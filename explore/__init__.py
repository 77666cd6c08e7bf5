"""The design-space sweep: what a bit, a term, a clock or a blend costs in gates and buys in dB.

- `explore.space`: the plan (which configurations `make explore` measures, and why).
- `explore.measure`: one point: gate count (Yosys, each block's netlist cached by its parameter
  set), pixels per clock per scene, PSNR against the float reference and the supersampled truth,
  and a bit-exact check through Verilator.
- `explore.sweep` (`python -m explore.sweep`, `make explore`): the points on Dask distributed, each
  result stored under a hash of its configuration and the source it was measured on;
  out/explore/results.json.
- `explore.report`: docs/tradeoffs.md and its plots, from the results.
- `explore.fit` (`make fit`): the smallest-GE configuration for some scenes at a PSNR target.

Layers: explore imports model, hdlbuild, sim and synth; nothing imports explore.
"""
