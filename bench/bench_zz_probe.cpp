// TEMPORARY probe, not committed
#include <cstdio>
#include "thermodec/nodes/load_model.h"
#include "thermodec/reduction/reduce_model.h"
#include "thermodec/decimation/decimate_nodes.h"
#include "thermodec/radiation/radiation_reference.h"
#include "thermodec/radiation/ray_scene.h"
#include "thermodec/radiation/face_view_factors.h"
#include "thermodec/environment/external_loads.h"
#include "thermodec/environment/orbit.h"
using namespace thermodec;
int main(){
  ThermalModel model = load_model(THERMODEC_SOURCE_DIR "/sample_models/satellite/model.json");
  ReduceSettings settings;
  const RadiationReference rr = prepare_radiation(model, model.radiation);
  const RayScene scene0(model.mesh);
  ExternalLoadSettings ls = settings.reference.simulation.loads; ls.seed = model.radiation.seed;
  LoadSamples samples;
  external_loads(model, scene0, rr.face_view_factors().sides, &rr.face_view_factors(), ls, {}, &samples);
  const int n=model.nodes.size();
  Eigen::VectorXd r=Eigen::VectorXd::Zero(n); r[0]=0.96;
  DecimationResult d=decimate_nodes(model.mesh,r,settings.reference.decimation);
  ThermalModel c=model; c.mesh=d.mesh;
  IncrementalStats st; FaceViewFactors vf;
  radiative_couplings_incremental(rr,c,&st,&vf);
  const RayScene scene(c.mesh);
  LoadReuse reuse; reuse.reference=&samples; reuse.changed_region=st.changed_box;
  const RayScene chf(st.changed_faces); reuse.changed_faces=&chf;
  std::printf("changed box %f %f %f - %f %f %f, changed faces %d\n", st.changed_box.min().x(), st.changed_box.min().y(), st.changed_box.min().z(), st.changed_box.max().x(), st.changed_box.max().y(), st.changed_box.max().z(), st.changed_faces.num_faces());
  const Loads li = external_loads(c, scene, vf.sides, nullptr, ls, {}, nullptr, &reuse);
  const Loads lf = external_loads(c, scene, vf.sides, nullptr, ls, {}, nullptr, nullptr);
}
