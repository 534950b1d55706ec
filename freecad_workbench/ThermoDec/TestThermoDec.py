"""Tests of the ThermoDec workbench, run headless by `freecadcmd -t TestThermoDec -M <ThermoDec>`.

Environment (set by CTest): PYTHONPATH holds the thermodec module, THERMODEC_CLI the CLI,
THERMODEC_TEST_OUTPUT a scratch folder in the build tree.
"""

import json
import os
import shutil
import subprocess
import tempfile
import unittest

import numpy as np

import FreeCAD
from FreeCAD import Vector

from thermodec_freecad import (coatings, export, files, merged_nodes, model_file, objects, plots, references,
                               results, runner, sample, temperature_field, tessellate, thermal_result)
from thermodec_freecad.errors import ThermoDecError

try:
    import thermodec
except ImportError:  # the workbench works without the core; the core-backed tests say so
    thermodec = None


def _output_dir(name):
    root = os.environ.get("THERMODEC_TEST_OUTPUT") or tempfile.mkdtemp(prefix="thermodec_fc_")
    path = os.path.join(root, name)
    shutil.rmtree(path, ignore_errors=True)
    os.makedirs(path)
    return path


def _edge_lengths(V, F):
    E = np.vstack([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    return np.linalg.norm(V[E[:, 0]] - V[E[:, 1]], axis=1)


def _boundary_edge_count(F):
    E = np.sort(np.vstack([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    _, counts = np.unique(E, axis=0, return_counts=True)
    return int(np.sum(counts == 1))


class _DocTest(unittest.TestCase):
    def setUp(self):
        self.doc = FreeCAD.newDocument("ThermoDecTest")

    def tearDown(self):
        for name in list(FreeCAD.listDocuments()):
            FreeCAD.closeDocument(name)


class AtomicOutput(unittest.TestCase):
    def test_a_planted_link_at_any_temporary_name_is_never_followed(self):
        folder = _output_dir("atomic_output")
        victim = os.path.join(folder, "victim.txt")
        with open(victim, "w") as f:
            f.write("keep")
        out = os.path.join(folder, "model.json")
        for pid in range(os.getpid() - 2, os.getpid() + 3):  # the old predictable names
            os.symlink(victim, "%s.tmp%d" % (out, pid))
        files.atomic_write_text(out, "{}\n")
        with open(victim) as f:
            self.assertEqual(f.read(), "keep")
        with open(out) as f:
            self.assertEqual(f.read(), "{}\n")

    def test_an_existing_output_keeps_its_mode_and_a_fifo_is_refused(self):
        folder = _output_dir("atomic_output_mode")
        out = os.path.join(folder, "r.json")
        with open(out, "w") as f:
            f.write("old")
        os.chmod(out, 0o600)
        files.atomic_write_text(out, "new")
        self.assertEqual(os.stat(out).st_mode & 0o777, 0o600)
        fifo = os.path.join(folder, "pipe.json")
        os.mkfifo(fifo)
        with self.assertRaises(ThermoDecError):
            files.atomic_write_text(fifo, "x")
        self.assertEqual(sorted(os.listdir(folder)), ["pipe.json", "r.json"])


class CoatingLibrary(unittest.TestCase):
    def test_every_coating_has_values_in_range_and_a_source(self):
        for name in ("white_paint", "black_paint", "mli_outer_layer", "osr", "solar_cell",
                     "bare_aluminium"):
            a, e, source = coatings.coating(name)
            self.assertTrue(0 < a <= 1 and 0 < e <= 1, name)
            self.assertTrue(source.startswith("["), name)

    def test_fcmat_card_sets_absorptivity_and_emissivity(self):
        folder = _output_dir("fcmat")
        card = os.path.join(folder, "Kapton.FCMat")
        with open(card, "w") as f:
            f.write("; test card\n[General]\nName = Kapton\n[Thermal]\nSolarAbsorptivity = 0.41\n"
                    "Emissivity = 0.66\n")
        doc = FreeCAD.newDocument("Card")
        try:
            analysis = objects.makeAnalysis(doc)
            mat = objects.makeMaterial(analysis, card=card, name="kapton")
            self.assertEqual((mat.Absorptivity, mat.Emissivity), (0.41, 0.66))
        finally:
            FreeCAD.closeDocument(doc.Name)


class MergedNodeLabels(unittest.TestCase):
    def test_a_long_member_list_shows_its_first_five_and_counts_the_rest(self):
        self.assertEqual(merged_nodes.label("a+2", ["a", "b", "c"]), "a+2 (merged: a, b, c)")
        members = ["n%02d" % k for k in range(20)]
        self.assertEqual(merged_nodes.label("n00+19", members),
                         "n00+19 (merged: n00, n01, n02, n03, n04, \u2026 (+15 more))")


class TemperatureField(unittest.TestCase):
    """The pure part of a result's display: statistics, field, colour map, legend."""

    # Two nodes, three times: a cycling node and an isothermal one (test input, not a solution).
    NODES = ["panel", "core"]
    T = np.array([[200.0, 230.0, 260.0], [300.0, 300.0, 300.0]])

    def test_node_statistics_are_min_time_average_and_max_per_node(self):
        low, mean, high = temperature_field.node_statistics(self.T)
        self.assertEqual(list(low), [200.0, 300.0])
        self.assertEqual(list(mean), [230.0, 300.0])
        self.assertEqual(list(high), [260.0, 300.0])
        self.assertEqual(temperature_field.statistics_table(self.NODES, self.T),
                         [("core", 300.0, 300.0, 300.0), ("panel", 200.0, 230.0, 260.0)])

    def test_field_is_a_statistic_or_one_time_step(self):
        self.assertEqual(list(temperature_field.node_field(self.T, "max")), [260.0, 300.0])
        self.assertEqual(list(temperature_field.node_field(self.T, 1)), [230.0, 300.0])
        self.assertEqual(temperature_field.field_name(2, [0.0, 1900.0, 3800.0]), "step 2 (t = 3800 s)")
        self.assertEqual(temperature_field.field_name("min"), "min over the orbit")
        with self.assertRaisesRegex(ThermoDecError, "time step 3 outside 0..2"):
            temperature_field.node_field(self.T, 3)
        with self.assertRaisesRegex(ThermoDecError, "field must be min, mean, max or a time step"):
            temperature_field.node_field(self.T, "hottest")

    def test_faces_take_their_nodes_value_matched_by_name(self):
        # The mesh lists its nodes in another order than the result.
        faces = temperature_field.face_values([1.0, 2.0], [0, 1, 1, 0], ["core", "panel"], self.NODES)
        self.assertEqual(list(faces), [2.0, 1.0, 1.0, 2.0])
        with self.assertRaisesRegex(ThermoDecError, "no temperature for node\\(s\\) dish"):
            temperature_field.face_values([1.0, 2.0], [0], ["dish"], self.NODES)

    def test_colour_map_runs_blue_to_red_in_the_legends_levels(self):
        low, high = temperature_field.colour_range([200.0, 260.0])
        self.assertEqual((low, high), (200.0, 260.0))
        c = temperature_field.colours([200.0, 260.0, 100.0, 999.0, 230.0], low, high)
        self.assertEqual(c[0], temperature_field.heat_colour(0.0))
        self.assertEqual(c[1], temperature_field.heat_colour(1.0))
        self.assertEqual((c[2], c[3]), (c[0], c[1]))  # clamped
        r, g, b = c[0]
        self.assertTrue(b > r and b > g)  # cold is blue
        r, g, b = c[1]
        self.assertTrue(r > g and r > b)  # hot is red
        bands, labels = temperature_field.legend(low, high)
        self.assertEqual(len(bands), temperature_field.LEVELS)
        self.assertTrue(set(c) <= {colour for _, colour in bands})  # the mesh shows legend colours only
        self.assertEqual([text for _, text in labels], ["200.0 K", "215.0 K", "230.0 K", "245.0 K", "260.0 K"])
        self.assertEqual(temperature_field.colour_range([250.0, 250.0]), (249.5, 250.5))  # flat: still a map

    def test_result_json_is_checked(self):
        good = {"nodes": self.NODES, "times_s": [0, 1, 2],
                "temperatures_K": {"panel": list(self.T[0]), "core": list(self.T[1])}}
        nodes, times, T = temperature_field.temperature_matrix(good)
        self.assertEqual(nodes, self.NODES)
        self.assertTrue(np.array_equal(T, self.T))
        good["temperatures_K"]["core"] = [300.0, 300.0]
        with self.assertRaisesRegex(ThermoDecError, "node 'core' has 2 temperatures for 3 times"):
            temperature_field.temperature_matrix(good)
        with self.assertRaisesRegex(ThermoDecError, "not a thermodec result"):
            temperature_field.temperature_matrix({"panel": 250.0})


class ResultObject(_DocTest):
    """ThermalResult on a hand-made two-node mesh: the field shown, its colours, undo."""

    def setUp(self):
        super().setUp()
        import Mesh
        self.analysis = objects.makeAnalysis(self.doc)
        self.mesh = self.doc.addObject("Mesh::FeaturePython", "Two")
        tessellate.ThermalMesh(self.mesh)
        self.mesh.Mesh = Mesh.Mesh([[Vector(0, 0, 0), Vector(1, 0, 0), Vector(0, 1, 0)],
                                    [Vector(1, 0, 0), Vector(1, 1, 0), Vector(0, 1, 0)],
                                    [Vector(0, 0, 1), Vector(1, 0, 1), Vector(0, 1, 1)]])
        self.mesh.FaceNode = [1, 1, 0]
        self.mesh.NodeNames = ["core", "panel"]
        self.result = thermal_result.makeResult(self.analysis, self.mesh, TemperatureField.NODES, [0.0, 1900.0, 3800.0],
                                                TemperatureField.T, seed=7, rays_per_face=300)

    def test_mean_is_shown_first_with_its_range_and_the_seed_used(self):
        self.assertEqual(list(self.mesh.FaceTemperature), [230.0, 230.0, 300.0])
        self.assertEqual((self.result.ColourMinK, self.result.ColourMaxK), (230.0, 300.0))
        self.assertEqual((self.result.Seed, self.result.RaysPerFace), (7, 300))
        self.assertEqual(len(self.mesh.FaceColors), 3)
        self.assertEqual(tuple(self.mesh.FaceColors[2])[:3], tuple(np.float32(temperature_field.heat_colour(1.0))))

    def test_time_step_and_min_are_chosen_by_property_and_undone(self):
        self.doc.UndoMode = 1
        self.doc.openTransaction("show step 0")
        thermal_result.set_field(self.result, 0)
        self.doc.commitTransaction()
        self.assertEqual(list(self.mesh.FaceTemperature), [200.0, 200.0, 300.0])
        self.assertEqual(self.result.Shown, "step 0 (t = 0 s)")
        self.assertEqual((self.result.ColourMinK, self.result.ColourMaxK), (200.0, 300.0))
        self.doc.undo()
        self.doc.recompute()
        self.assertEqual(self.result.Field, "mean")
        self.assertEqual(list(self.mesh.FaceTemperature), [230.0, 230.0, 300.0])
        thermal_result.set_field(self.result, "max")
        self.assertEqual(list(self.mesh.FaceTemperature), [260.0, 260.0, 300.0])
        with self.assertRaisesRegex(ThermoDecError, "time step 5 outside 0..2"):
            thermal_result.set_field(self.result, 5)

    def test_result_survives_save_and_reopen(self):
        path = os.path.join(_output_dir("result_fcstd"), "result.FCStd")
        self.doc.saveAs(path)
        FreeCAD.closeDocument(self.doc.Name)
        doc = FreeCAD.openDocument(path)
        result = [o for o in doc.Objects if objects.is_type(o, thermal_result.ThermalResult)][0]
        thermal_result.set_field(result, "min")
        self.assertEqual(list(result.ResultMesh.FaceTemperature), [200.0, 200.0, 300.0])
        self.assertEqual(result.Seed, 7)


class SampleSatellite(_DocTest):
    def setUp(self):
        super().setUp()
        self.analysis = sample.build_analysis(self.doc, max_edge="150 mm")

    def test_tessellation_is_closed_dense_and_tagged(self):
        tm = tessellate.tessellate(self.analysis)
        V, F = tessellate.mesh_arrays(tm)
        node_names = list(tm.NodeNames)
        self.assertEqual(len(node_names), 10)
        face_node = np.array(tm.FaceNode)
        self.assertEqual(len(face_node), len(F))
        self.assertTrue(np.all(face_node >= 0))
        self.assertEqual(set(face_node.tolist()), set(range(len(node_names))))
        # Every part is a closed solid, so the welded mesh has no boundary edge.
        self.assertEqual(_boundary_edge_count(F), 0)
        # Planar faces are subdivided: no edge longer than the requested 150 mm.
        self.assertLessEqual(float(np.max(_edge_lengths(V, F))), 150.0)
        self.assertAlmostEqual(tm.LongestEdge, float(np.max(_edge_lengths(V, F))), places=6)
        self.assertGreater(len(F), 1500)

    def test_the_background_tessellation_gives_the_in_process_mesh(self):
        self.analysis.OutputDirectory = _output_dir("background_tessellation")
        job = runner.tessellate_job(self.analysis)  # what the Tessellate command runs with QProcess
        self.assertEqual(job.steps[0][1][1], "-c")  # freecadcmd -c <worker>
        lines = []
        runner.run_blocking(job, log=lines.append)
        shares = [runner.stage_fraction(line) for line in lines if line.startswith("tessellate: ") and "/" in line]
        self.assertTrue(shares and shares[-1] == 1.0, lines[-5:])  # a shape meshed again counts again
        tm = tessellate.import_job(self.analysis, job.outputs)
        background = tessellate.mesh_arrays(tm) + (list(tm.FaceNode), list(tm.FaceMaterial), tm.LongestEdge)
        tm = tessellate.tessellate(self.analysis)
        here = tessellate.mesh_arrays(tm) + (list(tm.FaceNode), list(tm.FaceMaterial), tm.LongestEdge)
        self.assertEqual(background[1].tolist(), here[1].tolist())
        self.assertEqual(background[0].tolist(), here[0].tolist())  # bit for bit: same Mefisto, BREP exact
        self.assertEqual(background[2:], here[2:])

    def test_a_background_tessellation_of_an_edited_analysis_is_refused(self):
        self.analysis.OutputDirectory = _output_dir("background_tessellation_edited")
        job = runner.tessellate_job(self.analysis)
        runner.run_blocking(job)
        self.doc.getObject("Body").Placement.Base = Vector(0, 0, 10)  # moved while it ran
        self.doc.recompute()
        with self.assertRaisesRegex(ThermoDecError, "changed while tessellating: tessellate again"):
            tessellate.import_job(self.analysis, job.outputs)
        self.assertIsNone(self.analysis.ThermalMesh)

    def test_every_triangle_faces_out_of_its_solid(self):
        tm = tessellate.tessellate(self.analysis)
        V, F = tessellate.mesh_arrays(tm)
        body = np.array(tm.FaceNode) < 6  # body_* nodes come first
        cross = np.cross(V[F[body, 1]] - V[F[body, 0]], V[F[body, 2]] - V[F[body, 0]])
        centre = V[F[body]].mean(axis=1)
        # The body is a cube centred on the origin: outward normals point away from it.
        self.assertTrue(np.all(np.einsum("ij,ij->i", cross, centre) > 0))

    def test_export_is_si_and_lists_every_node(self):
        folder = _output_dir("export")
        json_path, mesh_path = export.write_model(self.analysis, os.path.join(folder, "model.json"))
        with open(json_path) as f:
            data = json.load(f)
        self.assertEqual(data["mesh"], "model.obj")
        self.assertEqual(data["unit_scale"], 1.0)
        self.assertEqual(len(data["nodes"]), 10)
        self.assertEqual(data["nodes"]["body_px"]["power"], 40.0)
        self.assertEqual(data["nodes"]["body_pz"]["material"], "osr")
        self.assertEqual(data["materials"]["solar_cell"], {"absorptivity": 0.75, "emissivity": 0.82})
        self.assertEqual(data["_material_sources"]["solar_cell"], coatings.coating("solar_cell")[2])
        self.assertEqual(data["environment"]["type"], "orbit")
        self.assertAlmostEqual(data["environment"]["altitude_km"], 600.0)
        self.assertEqual(len(data["conductances"]), 4 + 12)  # hinges, mounts; the body box's 12 edges
        V = np.array([[float(x) for x in line.split()[1:]] for line in open(mesh_path)
                      if line.startswith("v ")])
        # mm -> m: the wings reach y = +-2400 mm.
        self.assertAlmostEqual(float(V[:, 1].max() - V[:, 1].min()), 4.8, places=6)
        groups = [line.split()[1] for line in open(mesh_path) if line.startswith("g ")]
        self.assertEqual(sorted(groups), sorted(data["nodes"]))
        usemtl = {line.split()[1] for line in open(mesh_path) if line.startswith("usemtl ")}
        self.assertIn("solar_cell", usemtl)

    def test_cli_reads_the_export(self):
        cli = os.environ.get("THERMODEC_CLI")
        if not cli or not os.path.exists(cli):
            self.skipTest("THERMODEC_CLI not set")
        folder = _output_dir("cli")
        json_path, _ = export.write_model(self.analysis, os.path.join(folder, "model.json"))
        info_path = os.path.join(folder, "info.json")
        run = subprocess.run([cli, "info", json_path, "--json", info_path], capture_output=True, text=True)
        if "not implemented" in run.stderr:
            self.skipTest("thermodec info is not implemented in this build")
        self.assertEqual(run.returncode, 0, run.stderr)
        with open(info_path) as f:
            info = json.load(f)
        tm = self.analysis.ThermalMesh
        self.assertEqual(info["faces"], tm.Mesh.CountFacets)
        self.assertEqual(info["vertices"], tm.Mesh.CountPoints)
        self.assertEqual((info["boundary_edges"], info["non_manifold_edges"], info["components"]), (0, 0, 5))
        nodes = {n["name"]: n for n in info["nodes"]}
        self.assertEqual(len(nodes), 10)
        self.assertAlmostEqual(nodes["body_px"]["area_m2"], 1.0, places=9)
        self.assertEqual(nodes["body_pz"]["materials"], ["osr"])
        self.assertEqual(sorted(nodes["wing_plusy"]["materials"]), ["solar_cell", "white_paint"])

    def test_core_reads_the_exported_mesh_in_metres(self):
        folder = _output_dir("core_mesh")
        _, mesh_path = export.write_model(self.analysis, os.path.join(folder, "model.json"))
        mesh = thermodec.read_mesh(mesh_path)
        tm = self.analysis.ThermalMesh
        self.assertEqual(mesh.num_faces, tm.Mesh.CountFacets)
        stats = thermodec.mesh_stats(mesh)
        self.assertEqual((stats.boundary_edges, stats.non_manifold_edges, stats.degenerate_faces), (0, 0, 0))
        self.assertEqual(stats.components, 5)  # body, two wings, boom, dish
        areas = dict(zip(mesh.node_names, thermodec.node_areas_m2(mesh)))
        self.assertAlmostEqual(areas["body_px"], 1.0, places=9)  # 1000 mm x 1000 mm
        shapes = {o.Label: o.Shape for o in self.doc.Objects if o.TypeId == "Part::Feature"}
        self.assertAlmostEqual(areas["wing_plusy"], shapes["WingPlusY"].Area * 1e-6, places=9)
        # The dish is curved: its chordal mesh is slightly smaller than the B-rep surface.
        self.assertLess(areas["dish"], shapes["Dish"].Area * 1e-6)
        self.assertGreater(areas["dish"], 0.99 * shapes["Dish"].Area * 1e-6)
        cells = mesh.material_names.index("solar_cell")
        cell_area = float(np.sum(thermodec.face_areas(mesh.V, mesh.F)[mesh.face_material == cells]))
        self.assertAlmostEqual(cell_area, 2 * 0.8 * 1.8, places=9)  # the two wing fronts

    def test_import_results_tags_triangles_with_node_temperatures(self):
        folder = _output_dir("import")
        _, mesh_path = export.write_model(self.analysis, os.path.join(folder, "model.json"))
        names = list(self.analysis.ThermalMesh.NodeNames)
        given = {name: 250.0 + 5.0 * k for k, name in enumerate(names)}  # test input, not a solution
        feature, summary = results.import_results(self.analysis, mesh_path, {"temperatures_K": given})
        self.assertEqual(summary["faces"], self.analysis.ThermalMesh.Mesh.CountFacets)
        self.assertEqual((summary["temperature_min_K"], summary["temperature_max_K"]), (250.0, 295.0))
        for n, t in zip(feature.FaceNode, feature.FaceTemperature):
            self.assertEqual(t, given[feature.NodeNames[n]])
        del given["dish"]
        with self.assertRaisesRegex(ThermoDecError, "no temperature for node\\(s\\) dish"):
            results.import_results(self.analysis, mesh_path, given)

    def test_binding_loads_the_export(self):
        if thermodec is None or not hasattr(thermodec, "load_model"):
            self.skipTest("thermodec module without load_model in this build")
        folder = _output_dir("binding")
        json_path, _ = export.write_model(self.analysis, os.path.join(folder, "model.json"))
        model = thermodec.load_model(json_path)
        tm = self.analysis.ThermalMesh
        self.assertEqual(model.mesh.num_faces, tm.Mesh.CountFacets)
        self.assertEqual(sorted(model.mesh.node_names), sorted(tm.NodeNames))
        body_px = [n for n in model.nodes if n.name == "body_px"][0]
        self.assertEqual(body_px.power_W, 40.0)
        self.assertEqual(body_px.capacitance_J_per_K, 8000.0)
        self.assertEqual(model.materials[body_px.material].name, "mli_outer_layer")
        self.assertEqual(len(model.conductances), 4 + 12)
        self.assertEqual(model.environment.type, thermodec.EnvironmentType.orbit)
        self.assertAlmostEqual(model.environment.altitude_km, 600.0)
        self.assertAlmostEqual(model.environment.inclination_deg, 98.0)

    def test_document_round_trip_keeps_objects_and_tags(self):
        tm = tessellate.tessellate(self.analysis)
        tags = list(tm.FaceNode)
        path = os.path.join(_output_dir("fcstd"), "sat.FCStd")
        self.doc.saveAs(path)
        FreeCAD.closeDocument(self.doc.Name)
        doc2 = FreeCAD.openDocument(path)
        analysis = [o for o in doc2.Objects if objects.is_type(o, objects.ThermalAnalysis)][0]
        self.assertEqual(len(objects.members(analysis, objects.ThermalNode)), 10)
        self.assertEqual(list(analysis.ThermalMesh.FaceNode), tags)
        json_path, _ = export.write_model(analysis, os.path.join(os.path.dirname(path), "m.json"))
        self.assertTrue(os.path.exists(json_path))


class Robustness(_DocTest):
    def _box(self, name="Box"):
        import Part
        obj = self.doc.addObject("Part::Feature", name)
        obj.Shape = Part.makeBox(100, 200, 300)
        return obj

    def test_unassigned_faces_are_named(self):
        box = self._box()
        analysis = objects.makeAnalysis(self.doc)
        mat = objects.makeMaterial(analysis, "white_paint")
        objects.makeNode(analysis, [(box, ["Face1", "Face2"])], material=mat)
        with self.assertRaisesRegex(ThermoDecError, r"4 face\(s\) belong to no thermal node: Box.Face3"):
            tessellate.tessellate(analysis)

    def test_missing_material_is_named(self):
        box = self._box()
        analysis = objects.makeAnalysis(self.doc)
        node = objects.makeNode(analysis, [(box, "")], name="Lonely")
        with self.assertRaisesRegex(ThermoDecError, "node 'Lonely' has no material"):
            tessellate.tessellate(analysis)
        node.Material = objects.makeMaterial(analysis, absorptivity=1.5, emissivity=0.5, name="bad")
        with self.assertRaisesRegex(ThermoDecError, r"material 'bad': Absorptivity = 1.5 is outside"):
            tessellate.tessellate(analysis)

    def test_empty_shape_is_named(self):
        empty = self.doc.addObject("Part::Feature", "Empty")
        analysis = objects.makeAnalysis(self.doc)
        objects.makeNode(analysis, [(empty, "")], name="n", material=objects.makeMaterial(analysis, "osr"))
        with self.assertRaisesRegex(ThermoDecError, "'Empty' has an empty shape"):
            tessellate.tessellate(analysis)

    def test_face_in_two_nodes_is_named(self):
        box = self._box()
        analysis = objects.makeAnalysis(self.doc)
        mat = objects.makeMaterial(analysis, "osr")
        objects.makeNode(analysis, [(box, "")], name="a", material=mat)
        objects.makeNode(analysis, [(box, "Face3")], name="b", material=mat)
        with self.assertRaisesRegex(ThermoDecError, "face Box.Face3 is in two nodes"):
            tessellate.tessellate(analysis)

    def test_face_reference_follows_renumbering_after_recompute(self):
        import Part
        box = self._box()
        analysis = objects.makeAnalysis(self.doc)
        mat = objects.makeMaterial(analysis, "osr")
        top = objects.makeNode(analysis, [(box, "Face6")], name="top", material=mat)
        objects.makeNode(analysis, [(box, ["Face%d" % i for i in range(1, 6)])], name="rest", material=mat)
        top_centre = box.Shape.Faces[5].CenterOfMass
        # Same solid, faces in reverse order: what a recompute of an edited model can do.
        box.Shape = Part.makeSolid(Part.makeShell(list(reversed(box.Shape.Faces))))
        self.assertFalse(box.Shape.Faces[5].CenterOfMass.isEqual(top_centre, 1e-9))
        self.doc.recompute()  # the nodes depend on the box: their execute() repairs the references
        self.assertEqual(top.References[0][1], ("Face1",))
        self.assertTrue(box.Shape.Faces[0].CenterOfMass.isEqual(top_centre, 1e-9))
        self.assertEqual(references.check(top), [])  # nothing left to repair
        tm = tessellate.tessellate(analysis)
        self.assertEqual(tm.Mesh.CountFacets, len(tm.FaceNode))

    def test_vanished_face_is_an_error_not_a_guess(self):
        import Part
        box = self._box()
        analysis = objects.makeAnalysis(self.doc)
        node = objects.makeNode(analysis, [(box, "Face6")], name="top", material=objects.makeMaterial(analysis, "osr"))
        box.Shape = Part.makeBox(10, 10, 10).Faces[0]  # one face left, elsewhere
        self.doc.recompute()
        self.assertIn("Invalid", node.State)  # shown in error in the tree
        with self.assertRaisesRegex(ThermoDecError, "Box.Face6 no longer exists"):
            references.check(node)

    def test_automatic_nodes_per_solid_and_per_face(self):
        import Part
        obj = self.doc.addObject("Part::Feature", "Two")
        obj.Shape = Part.makeCompound([Part.makeBox(10, 10, 10),
                                       Part.makeBox(10, 10, 10, Vector(20, 0, 0))])
        analysis = objects.makeAnalysis(self.doc)
        analysis.DefaultMaterial = objects.makeMaterial(analysis, "black_paint")
        per_solid = objects.automatic_nodes(analysis, [obj], per="solid")
        self.assertEqual(len(per_solid), 2)
        self.assertEqual([len(n.References[0][1]) for n in per_solid], [6, 6])
        analysis.MaxEdgeLength = "5 mm"
        tm = tessellate.tessellate(analysis)
        self.assertEqual(sorted(set(tm.FaceNode)), [0, 1])
        for n in per_solid:
            self.doc.removeObject(n.Name)
        self.assertEqual(len(objects.automatic_nodes(analysis, [obj], per="face")), 12)


class AutomaticNodes(_DocTest):
    """Automatic nodes per face get the default panel's heat capacity and edge links
    (defaults.py); a transient orbit refuses nodes that store no heat."""

    def _two_box_satellite(self, physical_defaults=True):
        import Part
        obj = self.doc.addObject("Part::Feature", "Sat")  # 1 m body, 0.4 m instrument box beside it
        obj.Shape = Part.makeCompound([Part.makeBox(1000, 1000, 1000, Vector(-500, -500, -500)),
                                       Part.makeBox(400, 400, 400, Vector(-200, -200, 700))])
        analysis = objects.makeAnalysis(self.doc)
        analysis.DefaultMaterial = objects.makeMaterial(analysis, "white_paint")
        nodes = objects.automatic_nodes(analysis, [obj], per="face", physical_defaults=physical_defaults)
        objects.makeEnvironment(analysis, "orbit")
        analysis.AnalysisType = "transient_orbit"
        analysis.MaxEdgeLength = "500 mm"
        analysis.RaysPerFace = 200
        analysis.StepsPerOrbit = 36
        analysis.OutputDirectory = _output_dir("automatic_nodes")
        return analysis, nodes

    def test_faces_get_the_panel_heat_capacity_and_links_across_their_edges(self):
        analysis, nodes = self._two_box_satellite()
        self.assertAlmostEqual(analysis.PanelArealHeatCapacity, 2*0.3e-3*2810*960 + 25e-3*49.7*904)
        areas = sorted(round(n.Capacitance / analysis.PanelArealHeatCapacity, 9) for n in nodes)
        self.assertEqual(areas, [0.16] * 6 + [1.0] * 6)  # m^2: each face one panel
        self.assertIn("J/(m^2 K)", nodes[0].Note)
        links = objects.members(analysis, objects.Conductance)
        self.assertEqual(len(links), 24)  # 12 edges per box, none between the two solids
        solid_of = {n.Name: (n.Capacitance > analysis.PanelArealHeatCapacity / 2) for n in nodes}
        for c in links:
            self.assertEqual(solid_of[c.NodeA.Name], solid_of[c.NodeB.Name])
            # k t L / (d_a + d_b): square faces of side s meet over s at s/2 + s/2, so G = k t.
            self.assertAlmostEqual(c.Value, analysis.PanelSheetConductance, places=9)
        self.assertAlmostEqual(analysis.PanelSheetConductance, 0.078)

    def test_two_box_satellite_in_a_transient_orbit_stays_above_100_K(self):
        if thermodec is None:
            self.skipTest("thermodec module not built")
        analysis, _ = self._two_box_satellite()
        path, summary = results.simulate(analysis)
        coldest = min(summary.items(), key=lambda kv: kv[1]["min_K"])
        FreeCAD.Console.PrintMessage("ThermoDec test: two-box satellite, coldest node %s %.1f K, hottest max %.1f K\n"
                                     % (coldest[0], coldest[1]["min_K"], max(v["max_K"] for v in summary.values())))
        self.assertGreater(coldest[1]["min_K"], 100.0)
        with open(analysis.ModelFile) as f:
            model = json.load(f)
        self.assertEqual(len(model["conductances"]), 24)
        self.assertTrue(all(n["capacitance"] > 0 for n in model["nodes"].values()))

    def test_nodes_without_heat_capacity_are_refused_in_a_transient_orbit(self):
        analysis, nodes = self._two_box_satellite(physical_defaults=False)
        self.assertEqual(objects.members(analysis, objects.Conductance), [])
        with self.assertRaisesRegex(ThermoDecError, "'Sat_Face1'.* capacitance 0 J/K"):
            export.model_data(analysis)
        analysis.AllowArithmeticNodes = True  # on purpose: accepted
        export.model_data(analysis)


class TwoSidedSheets(_DocTest):
    def test_sheet_node_with_back_material_is_two_sided_in_the_core(self):
        import Part
        sheet = self.doc.addObject("Part::Feature", "Sheet")
        sheet.Shape = Part.makePlane(1000, 500)  # an open face, not a solid
        analysis = objects.makeAnalysis(self.doc)
        analysis.MaxEdgeLength = "250 mm"
        cells = objects.makeMaterial(analysis, "solar_cell")
        node = objects.makeNode(analysis, [(sheet, "")], name="panel", material=cells)
        node.BackMaterial = objects.makeMaterial(analysis, "black_paint")
        json_path, _ = export.write_model(analysis, os.path.join(_output_dir("sheet"), "model.json"))
        model = thermodec.load_model(json_path)
        back = np.asarray(model.mesh.face_back_material)
        self.assertTrue(np.all(back >= 0))
        self.assertEqual({model.materials[i].name for i in back}, {"black_paint"})
        self.assertAlmostEqual(float(np.sum(thermodec.face_areas(model.mesh.V, model.mesh.F))), 0.5, places=9)

    def test_unreadable_step_is_named(self):
        path = os.path.join(_output_dir("badstep"), "broken.step")
        with open(path, "w") as f:
            f.write("ISO-10303-21;\nthis is not STEP\n")
        with self.assertRaisesRegex(ThermoDecError, "broken.step"):
            objects.import_step(self.doc, path)


class StepRoundTrip(_DocTest):
    def test_step_export_read_and_tessellate_match_the_original(self):
        import Part
        shapes = sample.build_shapes(self.doc)
        path = os.path.join(_output_dir("step"), "satellite.step")
        Part.export(list(shapes.values()), path)
        imported = objects.import_step(self.doc, path)  # Part.read inside
        shape = imported.Shape
        self.assertEqual(len(shape.Solids), 5)
        original_area = sum(o.Shape.Area for o in shapes.values())
        self.assertAlmostEqual(shape.Area / original_area, 1.0, places=6)
        analysis = objects.makeAnalysis(self.doc)
        analysis.DefaultMaterial = objects.makeMaterial(analysis, "white_paint")
        analysis.MaxEdgeLength = "150 mm"
        nodes = objects.automatic_nodes(analysis, [imported], per="solid")
        self.assertEqual(len(nodes), 5)
        tm = tessellate.tessellate(analysis)
        V, F = tessellate.mesh_arrays(tm)
        self.assertEqual(_boundary_edge_count(F), 0)
        cross = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
        mesh_area = 0.5 * float(np.sum(np.linalg.norm(cross, axis=1)))
        # Curved faces (boom, dish) are chords of the surface: a little smaller, never larger.
        self.assertLess(mesh_area, original_area * (1 + 1e-9))
        self.assertGreater(mesh_area, original_area * 0.99)


class CoreRuns(_DocTest):
    """Simulation and decimation of the sample through the binding (coarse mesh: fast)."""

    def setUp(self):
        super().setUp()
        self.analysis = sample.build_analysis(self.doc, max_edge="400 mm")
        self.analysis.OutputDirectory = _output_dir("core_runs")

    def test_simulation_is_deterministic_and_tags_triangles(self):
        path, summary = results.simulate(self.analysis)
        self.assertEqual(sorted(summary), sorted(self.analysis.ThermalMesh.NodeNames))
        tm = self.analysis.ThermalMesh
        for n, t in zip(tm.FaceNode, tm.FaceTemperature):  # the workbench's time average, the core's mean
            self.assertAlmostEqual(t, summary[tm.NodeNames[n]]["mean_K"], places=9)
        result = objects.members(self.analysis, thermal_result.ThermalResult)[0]
        self.assertEqual((result.Seed, result.RaysPerFace), (self.analysis.Seed, self.analysis.RaysPerFace))
        self.assertEqual(result.ResultFile, path)
        for row in temperature_field.statistics_table(*thermal_result.matrix(result)[::2]):
            self.assertAlmostEqual(row[1], summary[row[0]]["min_K"], places=9)
            self.assertAlmostEqual(row[3], summary[row[0]]["max_K"], places=9)
        for node in summary.values():
            self.assertTrue(0 < node["min_K"] <= node["mean_K"] <= node["max_K"] < 1000)
        with open(path) as f:
            first = json.load(f)["temperatures_K"]
        results.simulate(self.analysis)
        with open(path) as f:
            self.assertEqual(json.load(f)["temperatures_K"], first)  # same seed, same numbers

    def test_the_background_simulate_job_gives_the_in_process_numbers(self):
        if not os.environ.get("THERMODEC_CLI") and not shutil.which("thermodec"):
            self.skipTest("no thermodec command")
        path, summary = results.simulate(self.analysis)  # thermodec.simulate_model, in-process
        with open(path) as f:
            first = json.load(f)["temperatures_K"]
        job = runner.simulate_job(self.analysis)  # what the Simulate command runs with QProcess
        self.assertEqual([argv[1] for _, argv in job.steps], ["simulate"])
        runner.run_blocking(job)
        path, summary_cli = results.import_simulation(self.analysis, job.outputs)
        with open(path) as f:
            self.assertEqual(json.load(f)["temperatures_K"], first)  # bit for bit
        self.assertEqual(summary_cli, summary)
        shown = [r for r in objects.members(self.analysis, thermal_result.ThermalResult)
                 if r.ResultMesh == self.analysis.ThermalMesh]
        self.assertEqual(len(shown), 1)
        self.assertEqual((shown[0].ResultFile, shown[0].Seed, self.analysis.ResultFile), (path, self.analysis.Seed, path))
        self.assertEqual(results.dense_result_current(self.analysis), path)  # Reduce reuses it

    def test_a_model_file_simulates_as_it_is_with_its_seed(self):
        results.simulate(self.analysis)
        self.analysis.Seed = 5  # the analysis changed since: the file's seed is the one used
        feature, result = results.simulate_model_file(self.analysis, self.analysis.ModelFile)
        self.assertEqual(result.Seed, 1)
        self.assertEqual(feature.Mesh.CountFacets, self.analysis.ThermalMesh.Mesh.CountFacets)
        with open(self.analysis.ResultFile) as f:
            same = json.load(f)["summary"]  # same file, same seed: same numbers
        for n, t in zip(feature.FaceNode, feature.FaceTemperature):
            self.assertAlmostEqual(t, same[feature.NodeNames[n]]["mean_K"], places=9)
        # A result.json imports with its time series (no seed recorded in the file).
        mesh_path = os.path.join(os.path.dirname(self.analysis.ModelFile), "model.obj")
        imported, summary = results.import_results(self.analysis, mesh_path, result.ResultFile, name="Imported")
        res = self.doc.getObject(summary["result"])
        self.assertEqual((res.Seed, res.ColourMinK, res.ResultFile), (-1, result.ColourMinK, result.ResultFile))
        self.assertEqual(list(imported.FaceTemperature), list(feature.FaceTemperature))

    def test_nastran_export_for_other_tools_reads_back_with_every_triangle(self):
        out = os.path.join(self.analysis.OutputDirectory, "model.bdf")
        files = results.export_for_tool(self.analysis, "nastran", out)
        self.assertEqual(files, [out])
        back = thermodec.load_model(out)
        self.assertEqual(len(back.mesh.F), len(self.analysis.ThermalMesh.FaceNode))
        self.assertEqual(sorted(back.mesh.node_names), sorted(self.analysis.ThermalMesh.NodeNames))

    def test_export_dialog_offers_the_cores_format_table(self):
        rows = results.exchange_formats()
        self.assertEqual([r["name"] for r in rows], [r["name"] for r in thermodec.export_formats()])
        esatan = [r for r in rows if r["name"] == "esatan"][0]
        self.assertEqual(results.file_dialog_filter(esatan), "ESATAN-TMS network (*.d)")
        self.assertEqual([r["output"] for r in rows if r["name"] == "vtk"], ["folder"])

    def test_decimation_keeps_every_node_and_its_area(self):
        results.simulate(self.analysis)
        feature, summary = results.decimate(self.analysis, 0.8)
        self.assertEqual(summary["nodes"], 10)
        self.assertLess(summary["faces"], 0.35 * summary["faces_before"])
        reduced = thermodec.load_model(os.path.join(self.analysis.OutputDirectory, "reduced", "model.json"))
        dense = thermodec.load_model(self.analysis.ModelFile)
        for a, b in zip(thermodec.node_areas_m2(dense.mesh), thermodec.node_areas_m2(reduced.mesh)):
            self.assertLessEqual(abs(b - a) / a, 0.005 + 1e-12)  # DecimationOptions default bound
        self.assertEqual(len(feature.FaceTemperature), summary["faces"])
        shown = [r for r in objects.members(self.analysis, thermal_result.ThermalResult) if r.ResultMesh == feature]
        self.assertEqual(len(shown), 1)  # the dense simulation on the reduced triangles, its seed kept
        self.assertEqual((shown[0].Seed, shown[0].ResultFile), (self.analysis.Seed, self.analysis.ResultFile))
        # The paper's question, for the record: how far the reduced model's temperatures are.
        diff = thermodec.compare_results(thermodec.simulate_model(dense), thermodec.simulate_model(reduced))
        FreeCAD.Console.PrintMessage("ThermoDec test: dense %d -> reduced %d faces, max |dT| %.2f K at %s\n"
                                     % (summary["faces_before"], summary["faces"], diff.max_abs_K, diff.node))
        results.decimate(self.analysis, 0.5)  # a second run replaces the mesh and its result
        self.assertEqual(len([r for r in objects.members(self.analysis, thermal_result.ThermalResult)
                              if r.ResultMesh is None or r.ResultMesh.Name == "ReducedMesh"]), 1)

    def test_the_background_decimate_job_gives_the_in_process_mesh(self):
        if not os.environ.get("THERMODEC_CLI") and not shutil.which("thermodec"):
            self.skipTest("no thermodec command")
        here, _ = results.decimate(self.analysis, 0.8)
        faces_here = tessellate.mesh_arrays(here)
        job = runner.decimate_job(self.analysis, 0.8)  # what the Decimate command runs with QProcess
        self.assertEqual([argv[1] for _, argv in job.steps], ["decimate"])
        runner.run_blocking(job)
        feature, summary = results.import_decimation(self.analysis, job.outputs)
        background = tessellate.mesh_arrays(feature)
        self.assertEqual(background[1].tolist(), faces_here[1].tolist())
        self.assertTrue(np.allclose(background[0], faces_here[0], rtol=0, atol=1e-6))  # mm, through OBJ text
        self.assertEqual(summary["faces"], len(background[1]))
        self.assertEqual(len([o for o in self.doc.Objects if o.Name.startswith("ReducedMesh")]), 1)

    def test_reduce_job_runs_the_cli_and_export_writes_the_reduced_model_until_an_input_changes(self):
        objects.members(self.analysis, objects.Environment)[0].EnvironmentType = "fixed_sun"
        self.analysis.RaysPerFace = 100
        self.analysis.MaxEdgeLength = "500 mm"
        job = runner.reduce_job(self.analysis, tolerance_K=5.0, plots=False)
        self.assertEqual([argv[1] for _, argv in job.steps], ["simulate", "reduce", "simulate"])
        runner.run_blocking(job)  # what the GUI's RunPanel runs with QProcess
        feature, info = results.import_reduction(self.analysis, job.outputs)
        self.assertEqual(info["faces_after"], feature.Mesh.CountFacets)
        self.assertLessEqual(info["max_temperature_difference_K"], 5.0)
        series = plots.orbit_series(self.analysis)  # the plot dock's data: original and reduced
        self.assertEqual(series["reduced"].shape, series["dense"].shape)
        # `thermodec simulate` of each model, seed for seed: within the tolerance the reduction verified
        self.assertLessEqual(float(np.abs(series["reduced"] - series["dense"]).max()), 5.0)
        tolerance, curves = plots.sensitivity_curves(plots.report_path(self.analysis))
        self.assertEqual((tolerance, len(curves)), (5.0, len(self.analysis.ThermalMesh.NodeNames)))
        self.assertEqual(results.model_for_tools(self.analysis), job.outputs["reduced_model"])
        out = os.path.join(self.analysis.OutputDirectory, "reduced.bdf")
        runner.run_blocking(runner.export_job(self.analysis, "nastran", out))
        self.assertEqual(thermodec.load_model(out).mesh.num_faces, feature.Mesh.CountFacets)
        self.assertEqual([argv[1] for _, argv in runner.reduce_job(self.analysis).steps], ["reduce", "simulate"],
                         [(r.Label, r.StaleReason, r.ResultFile, self.analysis.ResultFile) for r in
                          objects.members(self.analysis, thermal_result.ThermalResult)])  # the dense result is current
        self.analysis.MergeNodes = True  # passed through as --merge-nodes; not an input of the results
        reduce_argv = [argv for _, argv in runner.reduce_job(self.analysis).steps if argv[1] == "reduce"]
        self.assertIn("--merge-nodes", reduce_argv[0])
        self.analysis.MergeNodes = False
        node = objects.members(self.analysis, objects.ThermalNode)[0]
        node.Power = node.Power + 1.0  # an input changes: every result is stale, the dense model exported
        shown = objects.members(self.analysis, thermal_result.ThermalResult)
        self.assertTrue(all(r.Stale and r.Label.endswith("(stale)") for r in shown))
        self.assertIn("Power of '%s' changed" % node.Label, shown[0].StaleReason)
        self.assertEqual(results.model_for_tools(self.analysis), self.analysis.ModelFile)

    def test_the_in_process_reduction_merges_nodes_when_asked(self):
        objects.members(self.analysis, objects.Environment)[0].EnvironmentType = "fixed_sun"
        self.analysis.RaysPerFace = 100
        self.analysis.MaxEdgeLength = "500 mm"
        self.analysis.MergeNodes = True  # thermodec.reduce_with_node_merging, as reduce --merge-nodes
        feature, summary = results.reduce(self.analysis, tolerance_K=5.0, plots=False)
        self.assertLessEqual(summary["max_temperature_difference_K"], 5.0)
        merged = list(feature.MergedNodes)  # under ReducedMesh in the tree, with the dense nodes merged
        self.assertTrue(merged)
        for m in merged:
            self.assertEqual([objects.model_name(n) for n in m.MemberNodes], list(m.Members))
            self.assertIn(m.MergedName, feature.NodeNames)
        reduced = thermodec.load_model(self.analysis.ReducedModelFile)
        self.assertEqual(sorted(o for o, _ in reduced.node_map), sorted(self.analysis.ThermalMesh.NodeNames))
        results.simulate(self.analysis)  # the plot dock: every dense node against its merged node
        series = plots.orbit_series(self.analysis)
        self.assertIsNotNone(series["reduced"])
        self.assertEqual(sorted(series["merged_into"]), sorted(n for m in merged for n in m.Members))

    def test_reduce_progress_follows_the_clis_stage_lines(self):
        lines = ["reduce: model.json: 600 faces", "reduce: [   0.0 s] sampling: estimating",
                 "reduce: [   2.8 s] noise floor 0.06 K", "reduce: [   3.0 s]   sensitivity: 6/12 nodes swept (42 trials, about 9 s left)",
                 "reduce: [   9.0 s] prediction and reduction", "reduce: [  20.0 s] verification: max |dT|"]
        shares = [runner.stage_fraction(line) for line in lines]
        self.assertIsNone(shares[0])
        self.assertEqual(shares[1:], sorted(shares[1:]))
        self.assertAlmostEqual(shares[3], 0.15 + 0.55 / 2)
        merging = ["reduce: [   0.0 s] node merging: simulating the original",  # --merge-nodes: before the above
                   "reduce: [   1.3 s] node merging: 41 candidate pairs, each merged alone",
                   "reduce: [   5.0 s]   merged (0.1 K alone, 0.1 K with the merges so far): a + b",
                   "reduce: [   6.0 s] node merging: the first 1 merges traced: max |dT| 0.2 K"]
        shares = [runner.stage_fraction(line) for line in merging]
        self.assertEqual(shares, sorted(shares))
        self.assertLess(shares[-1], runner.stage_fraction(lines[-3]))

    def test_reduction_meets_its_tolerance_and_writes_the_core_outputs(self):
        # Fixed sun and few rays keep this fast (the orbit case takes ~1 min: see docs/freecad.md).
        objects.members(self.analysis, objects.Environment)[0].EnvironmentType = "fixed_sun"
        self.analysis.RaysPerFace = 100
        self.analysis.MaxEdgeLength = "500 mm"
        with self.assertRaisesRegex(thermodec.InvalidInput, "below twice the measured noise floor"):
            results.reduce(self.analysis, tolerance_K=0.01, plots=False)
        os.makedirs(self.analysis.OutputDirectory, exist_ok=True)
        bad_case = os.path.join(self.analysis.OutputDirectory, "bad_case.json")
        with open(bad_case, "w") as f:
            f.write('{"environment": {"type": "fixed_sun", "sun_direktion": [0, 1, 0]}}')
        with self.assertRaisesRegex(thermodec.InvalidInput, "sun_direktion"):  # before any simulation
            results.reduce(self.analysis, tolerance_K=5.0, plots=False, cases=[bad_case])
        feature, summary = results.reduce(self.analysis, tolerance_K=5.0, plots=False)
        self.assertLessEqual(summary["max_temperature_difference_K"], 5.0)
        self.assertLess(summary["faces"], 0.5 * summary["faces_before"])
        folder = os.path.join(self.analysis.OutputDirectory, "reduced")
        reduced = thermodec.load_model(os.path.join(folder, "model.json"))
        self.assertEqual(reduced.mesh.num_faces, summary["faces"])
        self.assertEqual(sorted(reduced.mesh.node_names), sorted(self.analysis.ThermalMesh.NodeNames))
        with open(summary["report"]) as f:
            self.assertEqual(json.load(f)["faces_after"], summary["faces"])
        self.assertEqual(list(summary["cases"]), ["model"])
        self.assertEqual(len(feature.FaceTemperature), summary["faces"])
        shown = [r for r in objects.members(self.analysis, thermal_result.ThermalResult) if r.ResultMesh == feature][0]
        self.assertEqual((shown.Seed, shown.RaysPerFace), (self.analysis.Seed, 100))  # the verified run's
        FreeCAD.Console.PrintMessage("ThermoDec test: reduce %d -> %d faces, max |dT| %.3f K, noise %.3f K\n"
                                     % (summary["faces_before"], summary["faces"],
                                        summary["max_temperature_difference_K"], summary["noise_floor_K"]))


SAMPLE_MODEL = os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir, "sample_models",
                            "satellite", "model.json")


def _cli_or_skip(test):
    cli = os.environ.get("THERMODEC_CLI")
    if thermodec is None or not cli:
        test.skipTest("needs the thermodec module and THERMODEC_CLI")
    return cli


def _info_json(cli, model, out):
    subprocess.run([cli, "info", model, "--json", out], check=True, stdout=subprocess.DEVNULL)
    with open(out) as f:
        info = json.load(f)
    for key in ("model", "mesh"):
        del info[key]
    return info


class ModelFiles(_DocTest):
    """A model file opened in the workbench (Open model file) and written back by its export."""

    def _extras_model(self, folder):
        """The sample satellite around the Moon, with a power schedule, a heater and a description."""
        with open(SAMPLE_MODEL) as f:
            data = json.load(f)
        data["mesh"] = os.path.join(os.path.dirname(os.path.abspath(SAMPLE_MODEL)), data["mesh"])
        env = data["environment"]
        env["central_body"] = "moon"
        del env["albedo"], env["earth_ir_flux"]  # the Moon's own values, not the Earth's
        del data["nodes"]["body_px"]["power"]
        data["nodes"]["body_px"]["power_schedule_W"] = [[0, 5.0], [1500.0, 45.0]]
        data["nodes"]["instrument"]["heater"] = {"on_K": 250.0, "off_K": 260.0, "power_W": 12.0}
        data["description"] = "kept by the workbench"
        data["nodes"]["boom"]["capacitance"] = 0.0  # an arithmetic node the file allows
        path = os.path.join(folder, "extras.json")
        with open(path, "w") as f:
            json.dump(data, f, indent=1)
        return path, data

    def test_keys_the_workbench_does_not_edit_are_written_back(self):
        cli = _cli_or_skip(self)
        folder = _output_dir("model_file_extras")
        path, original = self._extras_model(folder)
        analysis = model_file.open_model(self.doc, path)
        env = objects.members(analysis, objects.Environment)[0]
        self.assertEqual(list(env.KeptModelKeys), ['central_body = "moon"'])  # shown read-only
        self.assertEqual(env.getEditorMode("KeptModelKeys"), ["ReadOnly"])
        nodes = {objects.model_name(n): n for n in objects.members(analysis, objects.ThermalNode)}
        self.assertEqual(model_file.kept(nodes["instrument"]), {"heater": original["nodes"]["instrument"]["heater"]})
        out, _ = export.write_model(analysis, os.path.join(folder, "saved", "model.json"))
        with open(out) as f:
            saved = json.load(f)
        self.assertEqual(saved["environment"], original["environment"])
        self.assertEqual(saved["description"], original["description"])
        for name, entry in original["nodes"].items():
            for key in ("power_schedule_W", "heater", "power", "capacitance", "material", "back_material"):
                self.assertEqual(saved["nodes"][name].get(key), entry.get(key), (name, key))
        a, b = _info_json(cli, path, os.path.join(folder, "a.json")), _info_json(cli, out, os.path.join(folder, "b.json"))
        self.assertEqual(a["environment"], b["environment"])  # the Moon's radius, albedo and IR
        self.assertEqual(a["environment"]["central_body"]["name"] if isinstance(a["environment"].get("central_body"), dict)
                         else a["environment"].get("central_body"), "moon")
        self.assertAlmostEqual(a.pop("area_m2"), b.pop("area_m2"), delta=1e-6 * a["faces"])  # FreeCAD meshes in float
        for node_a, node_b in zip(a.pop("nodes"), b.pop("nodes")):
            self.assertAlmostEqual(node_a.pop("area_m2"), node_b.pop("area_m2"), delta=1e-6)
            self.assertEqual(node_a, node_b)
        self.assertEqual(a, b)
        loaded = {n.name: n for n in thermodec.load_model(out).nodes}  # the core reads what it read before
        first = {n.name: n for n in thermodec.load_model(path).nodes}
        for name in ("body_px", "instrument"):
            self.assertEqual(str(loaded[name].power_schedule_W), str(first[name].power_schedule_W))
            self.assertEqual(str(loaded[name].heater), str(first[name].heater))
        env.Albedo = 0.2  # an edited value is written, a kept one stays
        self.assertEqual(export.model_data(analysis)[0]["environment"]["albedo"], 0.2)

    def test_an_edit_drops_a_reduced_models_certificate(self):
        _cli_or_skip(self)
        path, _ = self._extras_model(_output_dir("model_file_certificate"))
        analysis = model_file.open_model(self.doc, path)
        model_file.keep(analysis, dict(model_file.kept(analysis), certificate={"tolerance_K": 0.5}))
        self.assertIn("certificate", export.model_data(analysis)[0])  # unedited: kept
        objects.members(analysis, objects.ThermalNode)[0].Capacitance *= 2
        self.assertNotIn("certificate", export.model_data(analysis)[0])  # no longer verified
        self.assertEqual(model_file.kept(analysis), {"description": "kept by the workbench"})

    def _merged_sample(self, folder):
        cli = _cli_or_skip(self)
        out = os.path.join(folder, "merged.json")
        subprocess.run([cli, "merge", SAMPLE_MODEL, "--group", "body_px,body_py,body_pz", "--group",
                        "wing_py,wing_my", "-o", out], check=True, stdout=subprocess.DEVNULL)
        return out

    def test_a_merged_model_lists_each_merged_node_with_its_members(self):
        folder = _output_dir("model_file_merged")
        path = self._merged_sample(folder)
        analysis = model_file.open_model(self.doc, path)
        mesh = analysis.ThermalMesh
        shown = [(m.Label, list(m.Members), m.Node.Label) for m in mesh.MergedNodes]  # the tree: under the mesh
        self.assertEqual(shown, [("body_px+2 (merged: body_px, body_py, body_pz)", ["body_px", "body_py", "body_pz"],
                                  "body_px+2"),
                                 ("wing_py+1 (merged: wing_py, wing_my)", ["wing_py", "wing_my"], "wing_py+1")])
        self.assertEqual(list(self.doc.getObjectsByLabel("body_px+2")[0].MergedFrom), ["body_px", "body_py", "body_pz"])
        self.assertNotIn(mesh.MergedNodes[0], analysis.Group)  # outputs, not inputs of the analysis
        out, _ = export.write_model(analysis, os.path.join(folder, "saved", "model.json"))
        with open(path) as f, open(out) as g:
            self.assertEqual(json.load(g)["node_map"], json.load(f)["node_map"])
        saved = os.path.join(folder, "merged.FCStd")  # the document keeps them
        self.doc.saveAs(saved)
        FreeCAD.closeDocument(self.doc.Name)
        doc = FreeCAD.openDocument(saved)
        mesh = [o for o in doc.Objects if "MergedNodes" in o.PropertiesList][0]
        self.assertEqual([m.MergedName for m in mesh.MergedNodes], ["body_px+2", "wing_py+1"])

    def test_a_reduced_mesh_with_a_node_map_links_the_dense_nodes_merged(self):
        folder = _output_dir("model_file_reduced_merged")
        path = self._merged_sample(folder)
        dense = model_file.open_model(self.doc, SAMPLE_MODEL)  # the original's nodes, as after Reduce
        feature, _ = results.import_results(dense, os.path.join(folder, "merged.obj"), None, name="ReducedMesh")
        made = merged_nodes.show_from_model_file(dense, feature, path)  # as import_reduction does
        self.assertEqual([[n.Label for n in m.MemberNodes] for m in made],
                         [["body_px", "body_py", "body_pz"], ["wing_py", "wing_my"]])
        results._remove_mesh(dense, "ReducedMesh")  # a new Reduce replaces them with the mesh
        self.assertFalse([o for o in self.doc.Objects if objects.is_type(o, merged_nodes.MergedNode)])
