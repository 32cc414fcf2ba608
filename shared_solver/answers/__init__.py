"""From fits to answers: which estimate answers each case, and the result a person reads.

:mod:`.projective` answers with the paper's projective geometry, :mod:`.pinhole` with what
a phone camera is; :mod:`.building` turns either into a :class:`..result.SolveResult`.
"""
