"""FreeCAD's FEM workbench imports thermodec's NASTRAN export as a mesh (run headless:
`freecadcmd -t TestExchangeFreeCAD -M tests/exchange`, THERMODEC_CLI and THERMODEC_SAMPLE set).
FreeCAD's own reader (FemMesh::readNastran) must see every GRID and CTRIA3 with the same area."""
import os
import subprocess
import shutil
import tempfile
import unittest

import FreeCAD
import Fem


def obj_triangles(path):
    v, tris = [], []
    for line in open(path):
        w = line.split()
        if w and w[0] == "v":
            v.append(FreeCAD.Vector(*[float(x) for x in w[1:4]]))
        elif w and w[0] == "f":
            idx = [int(x.split("/")[0]) - 1 for x in w[1:]]
            tris += [(idx[0], idx[k], idx[k + 1]) for k in range(1, len(idx) - 1)]
    return v, tris


def area(a, b, c):
    return 0.5 * (b - a).cross(c - a).Length


class ExchangeNastranInFreeCAD(unittest.TestCase):
    def test_fem_imports_the_bdf_with_every_grid_and_triangle_and_the_same_area(self):
        model = os.environ["THERMODEC_SAMPLE"]
        work = tempfile.mkdtemp(prefix="thermodec_fc_bdf_")
        self.addCleanup(shutil.rmtree, work, True)
        bdf = os.path.join(work, "satellite.bdf")
        subprocess.run([os.environ["THERMODEC_CLI"], "export", model, "--format", "nastran", "-o", bdf, "-q"], check=True)
        doc = FreeCAD.newDocument("exchange")
        Fem.insert(bdf, doc.Name)
        meshes = [o for o in doc.Objects if o.isDerivedFrom("Fem::FemMeshObject")]
        self.assertEqual(len(meshes), 1)
        fem = meshes[0].FemMesh
        v, tris = obj_triangles(os.path.join(os.path.dirname(model), "satellite.obj"))
        self.assertEqual(fem.NodeCount, len(v))
        self.assertEqual(fem.TriangleCount, len(tris))
        fem_area = 0.0
        for f in fem.Faces:
            a, b, c = (fem.Nodes[n] for n in fem.getElementNodes(f))
            fem_area += area(a, b, c)
        obj_area = sum(area(v[i], v[j], v[k]) for i, j, k in tris)
        # GRID* keeps ~15 significant digits; FreeCAD stores doubles.
        self.assertAlmostEqual(fem_area, obj_area, delta=1e-9 * obj_area)
        FreeCAD.closeDocument(doc.Name)
