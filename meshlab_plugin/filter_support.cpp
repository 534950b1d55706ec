#include "filter_support.h"

#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QJsonDocument>
#include <QJsonObject>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>

#include "document_mesh.h"

namespace thermodec_meshlab {
namespace {

// The model file last used since MeshLab started (any layer).
QString& session_model_file() {
  static QString path;
  return path;
}

// A model JSON in the folder of `mesh_file` whose "mesh" has the same stem.
QString model_beside(const QString& mesh_file) {
  if (mesh_file.isEmpty()) return QString();
  const QFileInfo mesh(mesh_file);
  const QDir dir = mesh.dir();
  if (!dir.exists()) return QString();
  for (const QFileInfo& json : dir.entryInfoList(QStringList() << "*.json", QDir::Files, QDir::Name)) {
    if (json.size() > 64 * 1024 * 1024) continue;
    QFile file(json.absoluteFilePath());
    if (!file.open(QIODevice::ReadOnly)) continue;
    const QJsonDocument doc = QJsonDocument::fromJson(file.readAll());
    if (!doc.isObject()) continue;
    const QString named = doc.object().value("mesh").toString();
    if (!named.isEmpty() && QFileInfo(named).completeBaseName() == mesh.completeBaseName())
      return json.absoluteFilePath();
  }
  return QString();
}

ModelFileChoice found_model_file(MeshModel& layer) {
  const QString used = layer_model_file(layer);
  if (!used.isEmpty() && QFileInfo(used).isFile()) return {used, "used last with this layer"};
  const QString beside = model_beside(layer_file(layer));
  if (!beside.isEmpty()) return {beside, "found beside the mesh"};
  const QString last = session_model_file();
  if (!last.isEmpty() && QFileInfo(last).isFile()) return {last, "used last since MeshLab started"};
  return {};
}

}  // namespace

void add_model_file_parameter(RichParameterList& params, MeshModel& layer, const QString& help) {
  // MeshLab's file widget shows a file only once browsed for: the label names the one it holds.
  const ModelFileChoice found = found_model_file(layer);
  const QString label = found.path.isEmpty() ? QString("Model file (none: defaults)")
                                             : QString("Model file (%1)").arg(QFileInfo(found.path).fileName());
  params.addParam(RichOpenFile(
      "model_file", found.path, QStringList() << "thermodec model (*.json)", label,
      help + html_escaped(found.path.isEmpty() ? QString() : " Now: " + found.path + " (" + found.how + ").")));
}

QString text_parameter(const RichParameterList& params, const QString& name) {
  if (!params.hasParameter(name)) return QString();
  const Value& v = params.getParameterByName(name).value();
  if (v.isFileName()) return v.getFileName().trimmed();
  if (v.isString()) return v.getString().trimmed();
  return QString();
}

ModelFileChoice choose_model_file(const RichParameterList& params, MeshModel& layer) {
  ModelFileChoice c{text_parameter(params, "model_file"), "given"};
  const ModelFileChoice found = found_model_file(layer);
  // The dialog's default is the file found: say how it was found, not "given".
  if (c.path.isEmpty() || QFileInfo(c.path) == QFileInfo(found.path)) c = found;
  if (!c.path.isEmpty()) {
    c.path = QFileInfo(c.path).absoluteFilePath();
    set_layer_model_file(layer, c.path);
    session_model_file() = c.path;
  }
  return c;
}

StageOf ordered_stages(std::vector<std::pair<std::string, double>> table) {
  auto at = std::make_shared<std::size_t>(0);  // entries before *at are done
  return [table, at](const std::string& m) {
    for (std::size_t i = *at; i < table.size(); ++i)
      if (m.find(table[i].first) != std::string::npos) {
        *at = i + 1;
        return table[i].second;
      }
    return -1.0;
  };
}

StageOf simulation_chain_stages() {
  return ordered_stages({{"sampling: estimating", 1}, {"building ray scene", 2}, {"view factors", 4},
                         {"IR Gebhart", 28}, {"external loads", 32}, {"thermal solve", 44},
                         {"sampling:", 47}, {"building ray scene", 48}, {"view factors", 50},
                         {"IR Gebhart", 82}, {"external loads", 86}, {"thermal solve", 97}});
}

void run_with_progress(vcg::CallBackPos* cb, const StageOf& stage_of,
                       const std::function<void(const std::function<void(const std::string&)>&)>& work,
                       const std::function<void(const std::string&)>& log) {
  std::mutex mutex;
  std::condition_variable wake;
  std::deque<std::string> messages;
  bool done = false;
  std::exception_ptr failure;
  // note: the core calls the progress function from its own threads (TBB workers); only this
  // queue is touched there, never a Qt object.
  std::thread worker([&] {
    try {
      work([&](const std::string& m) {
        std::lock_guard<std::mutex> lock(mutex);
        messages.push_back(m);
        wake.notify_one();
      });
    } catch (...) {
      failure = std::current_exception();
    }
    std::lock_guard<std::mutex> lock(mutex);
    done = true;
    wake.notify_one();
  });
  double percent = 0.0, stage = 0.0;
  std::string shown = "Thermal: starting";
  for (;;) {
    std::deque<std::string> batch;
    bool finished = false;
    {
      std::unique_lock<std::mutex> lock(mutex);
      wake.wait_for(lock, std::chrono::milliseconds(100), [&] { return done || !messages.empty(); });
      batch.swap(messages);
      finished = done;
    }
    for (const std::string& m : batch) {
      log(m);
      stage = std::max(stage, stage_of(m));
      const std::size_t text = m.find_first_not_of(' ');
      if (text != std::string::npos) shown = "Thermal: " + m.substr(text);
    }
    // Within a stage the bar creeps on towards (never past) the stage's end: the window shows
    // that work goes on.
    percent = std::max(percent, stage);
    percent += (std::min(99.0, stage + 8.0) - percent) * 0.01;
    if (cb != nullptr) cb(static_cast<int>(percent), shown.c_str());
    if (finished) break;
  }
  worker.join();
  if (failure) std::rethrow_exception(failure);
}

QString html_escaped(const QString& text) { return text.toHtmlEscaped(); }

}  // namespace thermodec_meshlab
