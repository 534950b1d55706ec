"""Face references of nodes and materials, and their re-check after a recompute.

FreeCAD names faces by index (Face7), and indices change when the model is edited and
recomputed. Each reference therefore keeps a signature (centre of mass and area, in mm);
before tessellation the reference is checked: a face whose signature no longer matches is
looked up by its signature among the object's faces and the reference repaired, or the
user gets an error naming the node and the face to re-select.
"""

import FreeCAD

# Relative tolerance on area and on centre distance (relative to the face's size): the
# signature only has to tell faces of one object apart, not measure them.
_TOL = 1e-6


from .errors import ThermoDecError


def normalise(refs):
    """[(obj, 'Face1'), (obj, ['Face2', 'Face3']), (obj, '')] -> LinkSubList value."""
    out = []
    for obj, subs in refs:
        if isinstance(subs, str):
            subs = [subs]
        # FreeCAD drops an entry with no sub-element; '' keeps it and means the whole shape.
        out.append((obj, list(subs) or [""]))
    return out


def _signature(face):
    c = face.CenterOfMass
    return "%.9g,%.9g,%.9g,%.9g" % (c.x, c.y, c.z, face.Area)


def _parse(sig):
    x, y, z, a = (float(v) for v in sig.split(","))
    return FreeCAD.Vector(x, y, z), a


def _matches(face, sig):
    c, a = _parse(sig)
    size = max(a, 1e-30) ** 0.5
    return abs(face.Area - a) <= _TOL * max(a, 1e-30) + 1e-12 and \
        (face.CenterOfMass - c).Length <= _TOL * size + 1e-9


def face_index(sub):
    if sub.startswith("Face") and sub[4:].isdigit():
        return int(sub[4:]) - 1
    return None


def expand(obj, subs):
    """Face sub-element names covered by (obj, subs): all faces when subs is empty."""
    shape = getattr(obj, "Shape", None)
    if shape is None or shape.isNull():
        raise ThermoDecError("'%s' has no shape" % obj.Label)
    subs = [s for s in subs if s]
    if not subs:
        return ["Face%d" % (i + 1) for i in range(len(shape.Faces))]
    for s in subs:
        if face_index(s) is None:
            raise ThermoDecError("'%s.%s' is not a face (nodes and materials reference faces)" %
                                  (obj.Label, s))
    return list(subs)


def store_signatures(owner):
    sigs = []
    for obj, subs in owner.References:
        shape = getattr(obj, "Shape", None)
        for s in subs:
            i = face_index(s)
            if shape is not None and i is not None and i < len(shape.Faces):
                sigs.append("%s.%s:%s" % (obj.Name, s, _signature(shape.Faces[i])))
    if list(owner.ReferenceSignatures) != sigs:
        owner.ReferenceSignatures = sigs


def check(owner):
    """Re-checks owner.References against the stored signatures after a recompute.

    Returns a list of human-readable repairs made (empty when nothing moved); raises
    ThermoDecError naming the owner and face when a face is gone."""
    stored = {}
    for entry in owner.ReferenceSignatures:
        key, sig = entry.split(":", 1)
        stored[key] = sig
    repairs = []
    new_refs = []
    changed = False
    for obj, subs in owner.References:
        shape = obj.Shape
        new_subs = []
        for s in subs:
            if not s:  # whole shape
                new_subs.append(s)
                continue
            i = face_index(s)
            sig = stored.get("%s.%s" % (obj.Name, s))
            ok = i is not None and i < len(shape.Faces) and (sig is None or _matches(shape.Faces[i], sig))
            if ok:
                new_subs.append(s)
                continue
            if sig is None:
                raise ThermoDecError("%s '%s': %s.%s does not exist (the shape has %d faces)" %
                                      (owner.Proxy.Type.split("::")[1], owner.Label, obj.Label, s,
                                       len(shape.Faces)))
            found = [k for k, f in enumerate(shape.Faces) if _matches(f, sig)]
            kind = owner.Proxy.Type.split("::")[1]
            if len(found) == 1:
                new_subs.append("Face%d" % (found[0] + 1))
                repairs.append("%s '%s': %s.%s moved to %s after a recompute" %
                               (kind, owner.Label, obj.Label, s, new_subs[-1]))
            elif i is not None and i < len(shape.Faces):
                # The face was edited in place (resized, moved): keep it by name.
                new_subs.append(s)
                repairs.append("%s '%s': %s.%s changed shape; kept by name, check it" %
                               (kind, owner.Label, obj.Label, s))
            else:
                raise ThermoDecError(
                    "%s '%s': face %s.%s no longer exists after a recompute (the shape has %d "
                    "faces) and no face matches its former position and area; re-select it" %
                    (kind, owner.Label, obj.Label, s, len(shape.Faces)))
            changed = True
        new_refs.append((obj, new_subs))
    if changed:
        owner.References = new_refs
        store_signatures(owner)
    return repairs
