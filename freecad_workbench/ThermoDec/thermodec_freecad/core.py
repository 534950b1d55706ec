"""Access to the thermodec core (pybind11 module `thermodec`).

Installed, the module sits in this workbench's folder; from a build tree it is found through
PYTHONPATH (build/python). Everything that computes on meshes or models goes through it."""

from .errors import ThermoDecError


def module():
    try:
        import thermodec
    except ImportError as e:
        raise ThermoDecError(
            "the thermodec Python module is not available (%s): build the thermodec_python target "
            "and put build/python on PYTHONPATH, or install with cmake --install" % e) from None
    return thermodec


def require(name):
    """The core function `name`, or a ThermoDecError saying this build does not have it yet."""
    td = module()
    if not hasattr(td, name):
        raise ThermoDecError("this build of thermodec has no '%s' yet" % name)
    return getattr(td, name)
