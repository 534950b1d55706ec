// `thermodec merge MODEL --group a,b[,...] [--group ...] -o OUT.json`: nodes merged by hand
// into isothermal nodes (nodes/merge_nodes.h); the model file and its mesh (OUT.obj beside it)
// carry the merged network and the node map.
#include <filesystem>
#include <iostream>

#include "commands.h"
#include "thermodec/common/errors.h"
#include "thermodec/nodes/merge_nodes.h"

namespace thermodec::cli {
namespace {

struct MergeArgs {
  std::string model;
  std::string output;
  std::vector<std::string> groups;
};

void run_merge(const MergeArgs& args) {
  namespace fs = std::filesystem;
  if (fs::path(args.output).extension() != ".json") throw InvalidInput(args.output + ": the output must be a .json model file");
  const ThermalModel model = load_model(args.model, model_load_options());
  const int n = static_cast<int>(model.nodes.size());
  std::vector<int> label(n);
  for (int i = 0; i < n; ++i) label[i] = i;
  std::vector<char> used(n, 0);
  for (const std::string& g : args.groups) {
    std::vector<std::string> patterns;
    std::size_t start = 0;
    for (std::size_t comma; (comma = g.find(',', start)) != std::string::npos; start = comma + 1)
      patterns.push_back(g.substr(start, comma - start));
    patterns.push_back(g.substr(start));
    const std::vector<int> members = nodes_matching(model, patterns);
    for (int i : members) {
      if (used[i]) throw InvalidInput("node '" + model.nodes[i].name + "' is in two --group options");
      used[i] = 1;
      label[i] = members.front();
    }
  }
  const ThermalModel merged = merge_nodes(model, node_merge_map(label, n));
  fs::path mesh = fs::path(args.output).replace_extension(".obj");
  for (const fs::path& in : {fs::path(args.model), model.mesh_path})
    if (fs::exists(mesh) && fs::exists(in) && fs::equivalent(mesh, in))
      throw InvalidInput(mesh.string() + " would overwrite an input");
  save_model(merged, args.output, mesh);
  std::cout << args.model << ": " << n << " -> " << merged.nodes.size() << " nodes; wrote " << args.output << " and "
            << mesh.string() << "\n";
  for (const auto& [original, into] : merged.node_map)
    if (original != into) std::cout << "  " << original << " -> " << into << "\n";
}

}  // namespace

void add_merge(CLI::App& app) {
  auto args = std::make_shared<MergeArgs>();
  auto* sub = app.add_subcommand(
      "merge",
      "thermodec merge MODEL --group a,b -o OUT.json: merge nodes into isothermal nodes (capacitances and powers\n"
      "summed, conductances to the rest summed, links inside dropped, faces keep their coatings); the model\n"
      "file records the node map (original -> merged). `reduce --merge-nodes` chooses merges itself.");
  sub->add_option("MODEL", args->model, "model file (.json) or mesh")->required()->check(CLI::ExistingFile);
  sub->add_option("-g,--group", args->groups, "comma-separated node names or shell patterns merged into one node (repeatable)")
      ->required();
  sub->add_option("-o,--output", args->output, "merged model file to write (.json; its mesh OUT.obj beside it)")->required();
  sub->callback([args] { run_guarded([&] { run_merge(*args); }); });
}

}  // namespace thermodec::cli
