"""SI units of the parameters a sweep can vary, for the column names.

Scene and protocol keys (config/scenes/README.md) by their last name, and the
options of triax_prepare. '-' is dimensionless, 'text' a name or a path.
A key not listed here gets the unit '?' (and triax_sweep says so)."""

SCENE_KEY_UNITS = {
    # material
    "density": "kg/m^3", "young_modulus": "Pa", "poisson_ratio": "-", "friction": "-",
    # particles
    "count": "-", "radius_min": "m", "radius_max": "m", "radius": "m", "fraction": "-", "seed": "-",
    "initial_void_ratio": "-", "aspect_ratio": "-", "sample_file": "text", "lengths": "m", "aspect": "-",
    # damping, time step, stability
    "model": "text", "ratio": "-", "time_step_ratio": "-", "max_overlap_ratio": "-", "max_energy_error": "-",
    # stages and stop criteria
    "name": "text", "type": "text", "strain_rate_dimensionless": "-", "strain_rate": "1/s",
    "confining_pressure": "Pa", "axial_axis": "text", "mean_stress": "Pa", "axial_strain": "-", "steps": "-",
    "ufr_below": "-", "deviator_below": "Pa", "softening": "-", "stress_tolerance": "-",
    # control and output
    "interval": "steps", "progress_seconds": "s", "quasi_static_threshold": "-", "strategy": "text",
    "gain": "-", "ki": "-", "kd": "-", "max_dimensionless_rate": "-", "max_rate_change": "-",
}

# triax_prepare options (README, Programs): name -> (unit, kind)
PREPARE_OPTIONS = {
    "psd": ("text", "path"), "pressure": ("Pa", "number"), "mu1": ("-", "number"),
    "target_void_ratio": ("-", "number"), "e_min": ("-", "number"), "e_max": ("-", "number"),
    "damping_ratio": ("-", "number"), "young_modulus": ("Pa", "number"), "poisson_ratio": ("-", "number"),
    "density": ("kg/m^3", "number"), "friction": ("-", "number"), "aspect": ("-", "text"),
    "shape": ("text", "text"), "particles": ("-", "integer"), "seed": ("-", "integer"),
}

# scene keys whose values are file paths (relative ones resolved against the
# folder of the file that names them)
SCENE_PATH_KEYS = {"sample_file"}


def scene_unit(tokens):
    last = [t for t in tokens if isinstance(t, str)][-1]
    return SCENE_KEY_UNITS.get(last, "?")
