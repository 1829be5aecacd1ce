"""Jobs of the workflow as one library call each: a rule's script unpacks its inputs, outputs
and parameters and calls one function here, which reads the files, calls the science and
writes the artefacts (the science itself reads and writes no artefact:
``tests/test_boundaries.py``)."""
