// PLY interop with MeshLab (the front end of the plugin): MeshLab keeps per-face labels only
// as face quality, so a round trip through meshlabserver must preserve every face's node id.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>

#include "mesh/mesh_test_util.h"
#include "thermodec/mesh/io.h"

using namespace thermodec;

TEST(MeshLabInterop, node_ids_survive_a_meshlabserver_round_trip_as_face_quality) {
  if (std::system("command -v meshlabserver >/dev/null 2>&1 && command -v Xvfb >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "meshlabserver or Xvfb not installed";
  const auto d = thermodec::test::temp_dir("meshlab");
  const Mesh cube = thermodec::test::unit_cube();
  write_mesh(d / "cube.ply", cube);
  const std::string cmd = "timeout 60 " THERMODEC_SOURCE_DIR "/scripts/with_xvfb meshlabserver -i '" + (d / "cube.ply").string() + "' -o '" +
                          (d / "back.ply").string() + "' -m fq >'" + (d / "log.txt").string() + "' 2>&1";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "meshlabserver failed, see " << d / "log.txt";
  const Mesh back = read_mesh(d / "back.ply");
  ASSERT_EQ(back.num_faces(), cube.num_faces());
  // MeshLab drops the name comments: ids come back, names become node_<id>.
  EXPECT_EQ(back.face_node, cube.face_node);
  EXPECT_EQ(back.node_names[5], "node_5");
  EXPECT_EQ(back.num_vertices(), 8);
}
