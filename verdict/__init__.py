"""The study's verdict: the gate's checks (`gate`, whose `write_verdict_files` is the one writer
of verdict.json and JUnit XML), the verdict files' bookkeeping (`verdict_files`: stale marks,
gate.txt, the log's verdict line), jobs that did not finish (`failed_jobs`) and the
study-vs-study comparison with its gate (`compare`). Imports analysis/ and the layers below.
"""
