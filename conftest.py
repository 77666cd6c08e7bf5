# pytest configuration of the whole repository. The project's packages (model, sim, synth,
# hdlbuild) are importable through `pip install -e .` (make setup); pytest puts this folder
# (the rootdir of this conftest) on sys.path, which is how the testbenches find `tb`.
