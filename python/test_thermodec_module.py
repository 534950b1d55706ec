"""Checks of the pybind11 module `thermodec` (run by CTest with Debian's python3)."""
import unittest

import numpy as np

import thermodec


class MeshCrossesAsNumpy(unittest.TestCase):
    def test_vertices_and_faces_round_trip(self):
        V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=float)
        F = np.array([[0, 1, 2]])  # int64 from numpy, int32 in the core
        mesh = thermodec.Mesh(V, F)
        self.assertEqual(mesh.num_faces, 1)
        np.testing.assert_array_equal(mesh.V, V)
        np.testing.assert_array_equal(mesh.F, F)
        np.testing.assert_array_equal(mesh.face_node, [-1])

    def test_model_lists_change_in_place(self):
        model = thermodec.ThermalModel()
        model.materials.append(thermodec.Material("white_paint", 0.2, 0.85))
        model.nodes.append(thermodec.Node("body", material=0, capacitance_J_per_K=2000.0))
        model.nodes[0].power_W = 5.0
        self.assertEqual(len(model.materials), 1)
        self.assertEqual(model.nodes[0].power_W, 5.0)
        self.assertIsNone(model.nodes[0].fixed_temperature_K)

    def test_errors_form_a_hierarchy(self):
        self.assertTrue(issubclass(thermodec.InvalidInput, thermodec.Error))
        self.assertTrue(issubclass(thermodec.IOError, thermodec.Error))
        self.assertTrue(issubclass(thermodec.Error, RuntimeError))


if __name__ == "__main__":
    unittest.main()
