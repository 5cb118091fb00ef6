"""Study files: schema, loading and validation.

A study file (TOML) says what to compute: the shot, the Almen control-curve
sweep, the d_min search and coverage settings, the real part (target), the
numerical fidelity and the seeds. See ``docs/study-files.md``.

    from peenflow.study import load_study
    study = load_study("studies/paper_al7075.toml")
    study.shot.diameter_mm, study.target.material.youngs_modulus_GPa   # 0.58, 71.0 (the file's units)

``load_study`` raises one :class:`StudyError` listing every problem (key path,
bad value, what is expected); ``validate_study`` returns those messages.
"""

from .canonical import canonical, canonical_json
from .errors import StudyError
from .fidelity import PRESETS as FIDELITY_PRESETS
from .fidelity import Fidelity
from .intensity import parse_intensity
from .items import JohnsonCook, Material, Shot, Strip
from .loader import LIBRARY_DIR, PROFILE_COMPONENTS, load_study, validate_study
from .model import SCHEMA_VERSION, Study, StudyInfo
from .sections import Almen, Coverage, Dmin, Execution, Seeds, ShotSection, Target

__all__ = [
    "load_study", "validate_study", "StudyError", "Study", "StudyInfo", "SCHEMA_VERSION",
    "Material", "JohnsonCook", "Shot", "Strip", "ShotSection", "Almen", "Dmin", "Coverage", "Target",
    "Fidelity", "FIDELITY_PRESETS", "Seeds", "Execution", "canonical", "canonical_json", "parse_intensity",
    "LIBRARY_DIR", "PROFILE_COMPONENTS",
]
