"""The workflow engine: a cached, resumable DAG of tasks on dask.

It knows nothing about shot peening.  Pieces, one module each:

* ``task``        declaring tasks (``@task``)
* ``graph``       points, sweeps and their upstream links
* ``canonical``   canonical parameter serialisation
* ``fingerprint`` code fingerprints blind to comments/docstrings
* ``content``     content hashes of Datasets (early cut-off)
* ``keys``        result keys and the typed reason a point must run
* ``reasons``     the reasons and states themselves
* ``store``       the directory store of netCDF results + manifests
* ``lease``       per-key leases (mkdir, heartbeat, unlock)
* ``checkpoint``  intermediate state of long tasks
* ``context``     what a running task may ask (progress, checkpoints, whether to stop)
* ``interrupt``   the per-process stop request (Ctrl-C, SIGTERM, SIGHUP)
* ``runner``      running one point
* ``planner``     status / dry-run without computing
* ``executor``    dask local or distributed execution
* ``report``      console output
* ``pipeline``    study file -> graph
* ``results``     opening a stage's results as one Dataset
"""

from .context import TaskContext
from .executor import SchedulerUnreachable, execute
from .graph import Graph, Group, Node, Sweep
from .pipeline import StudyFileError, load_graph
from .planner import plan
from .reasons import Reason, State
from .report import Reporter
from .results import ResultNotReady, stage_result
from .runner import Outcome
from .store import DirectoryStore
from .task import Task, task

__all__ = [
    "DirectoryStore", "Graph", "Group", "Node", "Outcome", "Reason", "Reporter",
    "ResultNotReady", "SchedulerUnreachable", "State", "StudyFileError", "Sweep", "Task", "TaskContext", "execute",
    "load_graph", "plan", "stage_result", "task",
]
