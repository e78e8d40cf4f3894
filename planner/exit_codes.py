"""The exit codes of the ``hapex`` commands (``run``, ``validate``, ``sweep``, ``reproduce``).

* :data:`EXIT_OK` (0): the run is ok (every claim reproduced or explained);
* :data:`EXIT_FAILED` (1): the input was fine but the run failed (no gait, contact lost, a
  singular finger: status "failed" with a reason), or a claim differs unexplained;
* :data:`EXIT_BAD_INPUT` (2): bad input or options (one ``FILE:LINE: key.path: message``
  line per error, nothing written);
* :data:`EXIT_INTERRUPTED` (130 = 128 + SIGINT) and :data:`EXIT_BROKEN_PIPE` (141 = 128 +
  SIGPIPE: the reader of stdout went away), as a shell reports them.
"""

from __future__ import annotations

EXIT_OK, EXIT_FAILED, EXIT_BAD_INPUT = 0, 1, 2
EXIT_INTERRUPTED = 130  # 128 + SIGINT
EXIT_BROKEN_PIPE = 141  # 128 + SIGPIPE: the reader of stdout went away

__all__ = ["EXIT_BAD_INPUT", "EXIT_BROKEN_PIPE", "EXIT_FAILED", "EXIT_INTERRUPTED", "EXIT_OK"]
