"""The workflow engine: a cached, resumable DAG of tasks on dask.

It knows nothing about shot peening.  Pieces, one module each:

* ``task``         declaring tasks (``@task``): their parameters, code identity and typed parameters
* ``graph``        points, sweeps and their upstream links
* ``growth``       sweeps that grow a dimension until a rule is satisfied
* ``plugin``       study file -> its pipeline (``pipeline = "module:function"``) -> graph
* ``canonical``    canonical parameter serialisation
* ``fingerprint``  code fingerprints blind to comments/docstrings
* ``content``      content hashes of Datasets (early cut-off)
* ``keys``         result keys and the typed reason a point must run
* ``reasons``      the reasons and states themselves
* ``store``        the store: results (+ manifests, failures) and run records (slots, progress,
                   checkpoints, leases, live runs); the only module that builds paths in a store
* ``atomic``       write to a unique temporary name, fsync, rename
* ``netcdf_io``    every netCDF read and write behind one process-wide lock
* ``conventions``  the CF attributes every stored result gets
* ``combine``      a sweep's results combined into one Dataset along its dims
* ``results``      opening a stage's results as one Dataset
* ``lease``        per-key leases (mkdir, heartbeat, unlock)
* ``checkpoint``   intermediate state of long tasks, and the one rule of what a checkpoint is worth
* ``context``      what a running task may ask (progress, checkpoints, whether to stop)
* ``interrupt``    the per-process stop request (Ctrl-C, SIGTERM, SIGHUP)
* ``cluster_stop`` that request passed on to the points on dask.distributed workers
* ``cores``        sharing a process's cores between the points it runs at once
* ``blas``         one BLAS thread in every process that computes (bit-identical cluster runs)
* ``runner``       running one point
* ``point_states`` each point's state and reason from the store, without computing
* ``planner``      status / dry-run: grow the graph, then state every point
* ``housekeeping`` the clean policy: what ``clean`` removes and keeps, and its lock
* ``executor``     dask local or distributed execution
* ``progress``     console output: progress bars or timestamped lines, summaries
"""

from .context import TaskContext
from .executor import SchedulerUnreachable, execute
from .graph import Graph, Group, Node, Sweep
from .plugin import StudyFileError, load_graph
from .planner import plan
from .reasons import Reason, State
from .progress import Reporter
from .results import ResultNotReady, stage_result
from .runner import Outcome
from .store import DirectoryStore
from .task import Task, task

__all__ = [
    "DirectoryStore", "Graph", "Group", "Node", "Outcome", "Reason", "Reporter",
    "ResultNotReady", "SchedulerUnreachable", "State", "StudyFileError", "Sweep", "Task", "TaskContext", "execute",
    "load_graph", "plan", "stage_result", "task",
]
