"""The state of an integration as three arrays, shared by the driver and every method.

An integration lives in a float array ``W`` of rows of the state's length ``n``, a float vector
``fst`` and an integer vector ``ist``, so that a compiled loop can pause (return to Python for
progress and the wall-clock budget) and resume where it stopped. The slots below are the ones the
driver (:mod:`.driver`) and the methods share; a method keeps its own from ``R_METHOD``,
``F_METHOD`` and ``S_METHOD`` on.
"""

# rows of W
R_Y = 0  # state at the end of the last step (current state)
R_F = 1  # f(t, y) there (methods that keep it)
R_YOLD = 2  # state at the start of the last step
R_FOLD = 3
R_BUF = 4  # scratch of the driver (dense output for events)
R_YFINAL = 5  # state where the segment ended
R_ATOL = 6  # absolute tolerance per component
R_RTOL = 7  # relative tolerance per component
R_YBEFORE = 8  # last located state on the near side of an event
R_METHOD = 9

# slots of fst
F_T = 0  # current time
F_TOLD = 1  # start of the last step
F_H = 2  # size of the next step to try (> 0)
F_HSTEP = 3  # signed size of the last step
F_TEND = 4
F_MAXSTEP = 5
F_DIR = 6  # +1 or -1
F_TFINAL = 7  # where the segment ended
F_TPAUSE = 8  # return to Python when t reaches this
F_TSTOP = 9  # last time reported (progress)
F_RES = 10  # longest interval between two samples of the event [time units]; 0: none
F_GOLD = 11  # event value and rate at the start of the step
F_DOLD = 12
F_TBEFORE = 13  # last located time on the near side of an event
F_BOLD = 14  # bound of the event's rate at the start of the step (inf: unknown)
F_METHOD = 16

# slots of ist
S_NFEV = 0
S_NSTEPS = 1  # accepted steps
S_NREJ = 2  # rejected attempts
S_IEVAL = 3  # samples written
S_INIT = 4  # 1 once the method is initialised
S_EVENT = 5  # 1: watch the event
S_FAIL = 6  # reason of a failure
S_MAXSTEPS = 7  # steps per call before returning to Python
S_DENSE = 8  # 1: the dense output of the last step is ready
S_ARMED = 9  # 1: the event has been positive, so a fall to zero counts
S_SAMPLE = 10  # 1 while the driver writes the samples of t_eval (a method may chain its dense output along them)
S_METHOD = 12

# return codes of a driver call and failure reasons
RUNNING, FINISHED, EVENT, FAILED = 0, 1, 2, 3
FAIL_SMALL_STEP, FAIL_NONFINITE, FAIL_RHS = 1, 2, 3  # step underflow, non-finite state, non-finite f
