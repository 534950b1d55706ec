"""Merged thermal nodes in the tree: a model whose nodes were merged (`thermodec merge`,
`reduce --merge-nodes`) carries a `node_map` (original node -> merged node, docs/model-format.md).

Under the mesh feature of such a model (ReducedMesh after Reduce, the ThermalMesh of an opened
model file) one MergedNode object per node made of two or more originals is labelled
"body_px+2 (merged: body_px, body_py, body_pz)"; its properties list the member names and link
the member ThermalNodes the document holds (the dense analysis' nodes after Reduce) and, for an
opened model, the merged ThermalNode itself. The objects are outputs: not part of the
analysis' inputs, replaced with the mesh. No GUI import here.
"""

import FreeCAD

from . import objects


class MergedNode(objects._Proxy):
    Type = "ThermoDec::MergedNode"

    def setup(self, obj):
        g = "Merged node"
        objects._add(obj, "App::PropertyString", "MergedName", g, "Name of the merged node in the model")
        objects._add(obj, "App::PropertyStringList", "Members", g, "Original nodes merged into it (node_map)")
        objects._add(obj, "App::PropertyLinkList", "MemberNodes", g,
                     "The members' ThermalNodes in this document (the dense analysis' nodes), when it has them")
        objects._add(obj, "App::PropertyLink", "Node", g, "The merged node's ThermalNode (an opened model file)")
        for prop in ("MergedName", "Members", "MemberNodes", "Node"):
            obj.setEditorMode(prop, 1)

    def onChanged(self, obj, prop):
        pass  # an output: its changes never make results stale


def members_of(node_map):
    """{merged node: [original, ...]} of a node_map, for merged nodes of two or more members;
    members in the map's order."""
    groups = {}
    for original, merged in (node_map or {}).items():
        groups.setdefault(str(merged), []).append(str(original))
    return {merged: names for merged, names in groups.items() if len(names) > 1}


def label(merged, members, max_shown=6):
    """The tree label: "body_px+2 (merged: body_px, body_py, body_pz)"; a longer member list
    than max_shown keeps its first max_shown - 1 and counts the rest ("a, b, c, d, e, \u2026 (+15
    more)": the Members property has them all), as the core's plots do."""
    if len(members) > max_shown:
        return "%s (merged: %s, \u2026 (+%d more))" % (merged, ", ".join(members[:max_shown - 1]),
                                                     len(members) - max_shown + 1)
    return "%s (merged: %s)" % (merged, ", ".join(members))


def _ensure_property(mesh):
    if "MergedNodes" not in mesh.PropertiesList:
        mesh.addProperty("App::PropertyLinkList", "MergedNodes", "Thermal tags",
                         "Merged nodes of this mesh's model, each with its original nodes (node_map)")
        mesh.setEditorMode("MergedNodes", 1)


def clear(mesh):
    """Removes the MergedNode objects shown under `mesh`."""
    if mesh is None or "MergedNodes" not in mesh.PropertiesList:
        return
    doc = mesh.Document
    names = [o.Name for o in mesh.MergedNodes]
    mesh.MergedNodes = []
    for name in names:
        if doc.getObject(name) is not None:
            doc.removeObject(name)


def show(analysis, mesh, node_map, nodes_of=None):
    """One MergedNode under `mesh` (a ThermalMesh-like feature) per merged node of `node_map`
    ({original: merged}); MemberNodes are the analysis' ThermalNodes of the members' names,
    Node the ThermalNode named like the merged node in `nodes_of` ({name: ThermalNode}) when
    given. Replaces the mesh's earlier ones. Returns the MergedNode objects, in the mesh's node order."""
    clear(mesh)
    groups = members_of(node_map)
    if not groups:
        return []
    _ensure_property(mesh)
    by_name = {objects.model_name(n): n for n in objects.members(analysis, objects.ThermalNode)}
    order = list(getattr(mesh, "NodeNames", [])) or list(groups)
    made = []
    for merged in sorted(groups, key=lambda m: order.index(m) if m in order else len(order)):
        obj = mesh.Document.addObject("App::FeaturePython", "MergedNode")
        MergedNode(obj)
        obj.MergedName = merged
        obj.Members = groups[merged]
        obj.Node = (nodes_of or {}).get(merged)
        obj.MemberNodes = [by_name[m] for m in groups[merged] if m in by_name and by_name[m] is not obj.Node]
        obj.Label = label(merged, groups[merged])
        if FreeCAD.GuiUp:
            from . import viewproviders
            viewproviders.ViewProvider(obj.ViewObject, "Node.svg")
            obj.ViewObject.Visibility = False
        made.append(obj)
    mesh.MergedNodes = made
    return made


def show_from_model_file(analysis, mesh, model_path):
    """show() with the node_map of the model file at `model_path` (none: clears)."""
    import json
    try:
        with open(model_path, encoding="utf-8") as f:
            node_map = json.load(f).get("node_map", {})
    except (OSError, ValueError):
        node_map = {}
    return show(analysis, mesh, node_map)
