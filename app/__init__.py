"""The command layer: the commands of the model (render, animation, precision, quality, needs;
`python -m app COMMAND ...` or `python -m app.COMMAND ...`). It stands above model, hdlbuild,
sim and synth and imports from them; of the layers only explore stands above it
(tests/test_layers.py holds the order)."""
