"""Checks of the pybind11 module `thermodec` (run by CTest with Debian's python3)."""
import os
import tempfile
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

    def test_central_body_schedule_and_heater_are_exposed(self):
        env = thermodec.Environment()
        self.assertEqual(env.central_body, "earth")
        env.set_central_body("mars")
        self.assertEqual(env.body_radius_m, 3389.5e3)
        self.assertEqual(env.albedo, 0.25)
        with self.assertRaises(thermodec.InvalidInput):
            env.set_central_body("venus")
        node = thermodec.Node("body", capacitance_J_per_K=2000.0)
        node.power_schedule_W = [(0.0, 5.0), (100.0, 45.0)]
        node.heater = thermodec.Thermostat(270.0, 275.0, 10.0)
        self.assertEqual(node.power_schedule_W[1], (100.0, 45.0))
        self.assertEqual(node.heater.off_K, 275.0)

    def test_node_merging_is_offered_and_checks_its_keep_patterns_first(self):
        sample = os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "sample_models",
                              "satellite", "model.json")
        model = thermodec.load_model(sample)
        self.assertEqual(model.node_map, [])
        model.node_map = [("a", "a+1"), ("b", "a+1")]
        self.assertEqual(model.node_map[1], ("b", "a+1"))
        model.node_map = []
        settings = thermodec.ReduceSettings()
        settings.tolerance_K = 1.0
        merge = thermodec.NodeMergeSettings()
        self.assertEqual((merge.tolerance_share, merge.keep), (0.6, []))
        merge.keep = ["no_such_node*"]
        with self.assertRaisesRegex(thermodec.InvalidInput, "no_such_node"):  # before any simulation
            thermodec.reduce_with_node_merging(model, settings, merge)
        merge.keep, merge.tolerance_share = [], 1.5
        with self.assertRaisesRegex(thermodec.InvalidInput, "share"):
            thermodec.reduce_with_node_merging(model, settings, merge)

    def test_radiation_settings_expose_the_per_node_ray_budget(self):
        model = thermodec.ThermalModel()
        self.assertEqual(model.radiation.min_rays_per_node, 250000)
        model.radiation.min_rays_per_node = 0
        self.assertEqual(model.radiation.min_rays_per_node, 0)

    def test_errors_form_a_hierarchy(self):
        self.assertTrue(issubclass(thermodec.InvalidInput, thermodec.Error))
        self.assertTrue(issubclass(thermodec.IOError, thermodec.Error))
        self.assertTrue(issubclass(thermodec.Error, RuntimeError))


def unit_cube():
    """Closed unit cube [m], 12 triangles, outward counter-clockwise."""
    V = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], dtype=float)
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    F = np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))])
    return V, F


def write_cube_model(folder, model_json):
    """cube.obj (one node "cube") and model.json with the given text in `folder`; the path."""
    V, F = unit_cube()
    mesh = thermodec.Mesh(V, F)
    mesh.node_names = ["cube"]
    mesh.face_node = np.zeros(12, dtype=int)
    thermodec.write_mesh(os.path.join(folder, "cube.obj"), mesh)
    path = os.path.join(folder, "model.json")
    with open(path, "w") as f:
        f.write(model_json)
    return path


class CoreFunctions(unittest.TestCase):
    def test_obj_round_trip_keeps_groups_and_materials(self):
        V, F = unit_cube()
        mesh = thermodec.Mesh(V, F)
        mesh.node_names = ["bottom", "rest"]
        mesh.material_names = ["osr", "white_paint"]
        mesh.face_node = np.array([0, 0] + [1] * 10)
        mesh.face_material = np.array([0, 0] + [1] * 10)
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "cube.obj")
            thermodec.write_mesh(path, mesh)
            back = thermodec.read_mesh(path)
        self.assertEqual(back.num_faces, 12)
        self.assertEqual(back.num_vertices, 8)
        names = [back.node_names[i] for i in back.face_node]
        self.assertEqual(names.count("bottom"), 2)
        self.assertEqual(set(back.material_names), {"osr", "white_paint"})

    def test_missing_file_raises_the_core_error_with_its_name(self):
        with self.assertRaisesRegex(thermodec.IOError, "no_such_mesh.obj"):
            thermodec.read_mesh("/nonexistent/no_such_mesh.obj")

    def test_bad_input_raises_invalid_input(self):
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "bad.obj")
            with open(path, "w") as f:
                f.write("v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n")
            with self.assertRaises(thermodec.InvalidInput) as caught:
                thermodec.read_mesh(path)
            self.assertIn("bad.obj", str(caught.exception))

    def test_cube_statistics_and_automatic_nodes(self):
        V, F = unit_cube()
        mesh = thermodec.Mesh(V, F)
        stats = thermodec.mesh_stats(mesh)
        self.assertEqual((stats.faces, stats.components, stats.boundary_edges), (12, 1, 0))
        self.assertAlmostEqual(stats.area_m2, 6.0, places=12)
        thermodec.assign_automatic_nodes(mesh)
        self.assertEqual(len(mesh.node_names), 6)  # one per side of the cube
        self.assertTrue(np.all(mesh.face_node >= 0))
        np.testing.assert_allclose(thermodec.node_areas_m2(mesh), [1.0] * 6, rtol=1e-12)


class ModelErrors(unittest.TestCase):
    def test_unknown_material_is_named_with_its_key(self):
        with tempfile.TemporaryDirectory() as folder:
            path = write_cube_model(folder, '{"mesh": "cube.obj", "materials": {"osr": {"absorptivity": 0.08,'
                                            ' "emissivity": 0.8}}, "nodes": {"cube": {"material": "gold"}}}')
            with self.assertRaisesRegex(thermodec.InvalidInput, "nodes.cube.material"):
                thermodec.load_model(path)


class LoadCases(unittest.TestCase):
    def test_case_file_moves_only_what_it_names_and_reaches_reduce_settings(self):
        with tempfile.TemporaryDirectory() as folder:
            path = write_cube_model(folder, '{"mesh": "cube.obj", "environment": {"type": "orbit",'
                                            ' "altitude_km": 650, "day_of_year": 172}}')
            model = thermodec.load_model(path)
            case_path = os.path.join(folder, "cold.json")
            with open(case_path, "w") as f:
                f.write('{"environment": {"type": "orbit", "day_of_year": 355}}')
            case = thermodec.load_case(case_path, model)
            self.assertEqual(case.name, "cold")
            self.assertEqual(case.environment.day_of_year, 355)
            self.assertEqual(case.environment.altitude_km, 650)
            self.assertEqual(thermodec.with_case(model, case).environment.day_of_year, 355)
            settings = thermodec.ReduceSettings()
            settings.extra_cases = [case]
            self.assertEqual(settings.extra_cases[0].name, "cold")
            with open(case_path, "w") as f:
                f.write('{"environment": {"type": "orbit", "day_of_yaer": 355}}')
            with self.assertRaisesRegex(thermodec.InvalidInput, "day_of_yaer"):
                thermodec.load_case(case_path, model)


class SimulateIsTheCliSimulate(unittest.TestCase):
    # (Bit-identity with `thermodec simulate`, export and MeshLab on the sample: the CTest test
    # meshlab.front_doors_give_bit_identical_temperatures.)
    def test_seed_argument_is_the_models_seed(self):
        with tempfile.TemporaryDirectory() as folder:
            model = thermodec.load_model(write_cube_model(folder, '{"mesh": "cube.obj"}'))
            model.radiation.rays_per_face = 64
            model.radiation.min_rays_per_node = 0
            a = thermodec.simulate_model(model, seed=7, noise_target_K=0.0)
            model.radiation.seed = 7
            b = thermodec.simulate_model(model, noise_target_K=0.0)
            np.testing.assert_array_equal(a.temperature_K, b.temperature_K)
            self.assertEqual(model.radiation.seed, 7)

    def test_noise_targeting_is_on_by_default(self):
        with tempfile.TemporaryDirectory() as folder:
            model = thermodec.load_model(write_cube_model(folder, '{"mesh": "cube.obj"}'))
            model.radiation.rays_per_face = 64
            model.radiation.min_rays_per_node = 0
            messages = []
            r = thermodec.simulate_model(model, messages.append)
            self.assertEqual(list(r.nodes), ["cube"])
            self.assertTrue(any(m.startswith("sampling:") for m in messages), messages)


class CostlyRunsAreRefusedBeforeAnyWork(unittest.TestCase):
    """The core's cost check, as the CLI applies it: a run estimated at hours of work is refused
    at once, naming the setting, unless force=True."""

    def costly_cube(self, folder):
        # A million load positions on an orbit: hours of thermal solve.
        return thermodec.load_model(write_cube_model(
            folder, '{"mesh": "cube.obj", "environment": {"type": "orbit"}, '
            '"analysis": {"type": "transient_orbit", "steps_per_orbit": 1000000}}'))

    def test_simulate_export_and_reduce_refuse(self):
        with tempfile.TemporaryDirectory() as folder:
            model = self.costly_cube(folder)
            for call in (lambda: thermodec.simulate_model(model, noise_target_K=0.0),
                         lambda: thermodec.simulate_model(model),
                         lambda: thermodec.export_model(model, "esatan", os.path.join(folder, "m.d")),
                         lambda: thermodec.reduce_model(model)):
                with self.assertRaises(thermodec.InvalidInput) as caught:
                    call()
                message = str(caught.exception)
                self.assertIn("over the limit", message)
                self.assertIn("analysis.steps_per_orbit = 1000000", message)
                self.assertIn("force=True", message)
            self.assertFalse(os.path.exists(os.path.join(folder, "m.d")))

    def test_within_the_limits_nothing_changes(self):
        with tempfile.TemporaryDirectory() as folder:
            model = thermodec.load_model(write_cube_model(folder, '{"mesh": "cube.obj"}'))
            model.radiation.rays_per_face = 64
            model.radiation.min_rays_per_node = 0
            a = thermodec.simulate_model(model, noise_target_K=0.0)
            b = thermodec.simulate_model(model, noise_target_K=0.0, force=True)
            np.testing.assert_array_equal(a.temperature_K, b.temperature_K)


class BadFilesRaiseInsteadOfCrashing(unittest.TestCase):
    """Front ends (FreeCAD, scripts) call the core through this module: files that once crashed
    or hung the host process must raise a thermodec error."""

    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.dir.cleanup()

    def path(self, name, data):
        p = os.path.join(self.dir.name, name)
        with open(p, "wb") as f:
            f.write(data)
        return p

    def test_ply_declaring_the_vertex_element_twice(self):
        p = self.path("twice.ply", b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                      b"property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                      b"element vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n"
                      b"0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n0 0 0\n")
        with self.assertRaisesRegex(thermodec.InvalidInput, "declared twice"):
            thermodec.read_mesh(p)

    def test_ply_with_an_enormous_unused_element(self):
        p = self.path("huge.ply", b"ply\nformat binary_little_endian 1.0\nelement junk 9000000000000000000\n"
                      b"property uchar a\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                      b"end_header\n")
        with self.assertRaisesRegex(thermodec.InvalidInput, "junk"):
            thermodec.read_mesh(p)

    def test_deeply_nested_model_json(self):
        self.path("m.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
        p = self.path("model.json", b'{"mesh": "m.obj", "radiation": {"seed": ' + b"[" * 100000 + b"]" * 100000 + b"}}")
        with self.assertRaisesRegex(thermodec.InvalidInput, "nested deeper"):
            thermodec.load_model(p)

    def test_tiny_unit_scale(self):
        self.path("m.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
        p = self.path("model.json", b'{"mesh": "m.obj", "unit_scale": 1e-200}')
        with self.assertRaisesRegex(thermodec.InvalidInput, "unit_scale"):
            thermodec.load_model(p)

    def test_device_as_mesh(self):
        link = os.path.join(self.dir.name, "zero.stl")
        os.symlink("/dev/zero", link)
        with self.assertRaisesRegex(thermodec.IOError, "not a regular file"):
            thermodec.read_mesh(link)



class ExportFormats(unittest.TestCase):
    """The core's table of export formats, as the FreeCAD workbench reads it."""

    def test_the_table_lists_the_formats_with_what_the_dialogs_need(self):
        rows = thermodec.export_formats()
        self.assertEqual([r["name"] for r in rows][:5], ["nastran", "esatan", "sinda", "vtk", "csv"])
        for r in rows:
            self.assertTrue(r["title"] and r["help"] and r["extensions"], r)
            self.assertIn(r["output"], ("file", "folder", "prefix"))
        nastran = rows[0]
        self.assertFalse(nastran["needs_simulation"])
        self.assertEqual(nastran["extensions"][0], ".bdf")
        self.assertEqual(str(thermodec.default_export_output("esatan", "/tmp/sat")), "/tmp/sat.d")
        self.assertEqual(str(thermodec.default_export_output("vtk", "/tmp/sat")), "/tmp/sat_vtk")

    def test_an_unknown_format_names_every_choice(self):
        with self.assertRaises(thermodec.InvalidInput) as caught:
            thermodec.default_export_output("esatn", "/tmp/sat")
        for r in thermodec.export_formats():
            self.assertIn(r["name"], str(caught.exception))


if __name__ == "__main__":
    unittest.main()
