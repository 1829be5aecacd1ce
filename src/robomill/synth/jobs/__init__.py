"""Jobs of the virtual cell's rules as one library call each: a ``synth_*`` rule's script calls
one function here, which reads its inputs, runs the simulator and writes the raw files (only the
simulators' scripts import :mod:`robomill.synth`)."""
