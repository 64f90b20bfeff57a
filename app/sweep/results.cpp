#include "app/sweep/results.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "app/output_file.hpp"
#include "sim/mpm/schemes/scheme_label.hpp"
#include "sim/scene/scene.hpp"

namespace apiclab::sweep {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

}  // namespace

std::string number_text(double v, int digits) {
  if (std::isnan(v)) return "";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

double RunResult::error(const std::string& name) const {
  if (name == "displacement") return ref.displacement;
  if (name == "com") return ref.com;
  if (name == "kinetic") return ref.kinetic;
  if (name == "elastic") return ref.elastic;
  if (name == "energy") return present ? rec.conservation.max_energy : kNaN;
  if (name == "angular") return present ? rec.conservation.max_angular : kNaN;
  if (name == "rigid") return rigid;
  return kNaN;
}

std::vector<RunResult> collect(const Spec& spec, const Plan& plan, const std::string& out_dir) {
  std::vector<RunResult> results(plan.runs.size());
  std::map<std::size_t, metrics::RunFrames> reference_frames;
  for (std::size_t i = 0; i < plan.runs.size(); ++i) {
    RunResult& r = results[i];
    r.run = &plan.runs[i];
    const std::string dir = run_dir(out_dir, plan.runs[i]);
    const double nan = kNaN;
    r.ref = {nan, nan, nan, nan, nan};
    if (!record_complete(dir)) {
      r.rec.fail_message = read_refusal(dir);
      r.outcome = r.rec.fail_message.empty() ? "no_result" : "refused";
      continue;
    }
    r.present = true;
    r.rec = read_record(dir);
    if (r.rec.blew_up)
      r.outcome = "blew_up";
    else if (r.rec.unconverged_steps > 0)
      r.outcome = "not_converged";
    else if (r.rec.noise > spec.noise_threshold)
      r.outcome = "noisy";
    else
      r.outcome = "completed";
    if (r.rec.blew_up) continue;
    const metrics::RunFrames frames = read_frames(dir);
    if (spec.known_answer == "rigid_rotation") {
      // Each object's centre, velocity and spin as the run's scene states them.
      const SceneDesc scene = load_scene(plan.runs[i].scene_path, plan.runs[i].overrides);
      std::vector<metrics::RigidMotion> motions;
      for (const ObjectDesc& o : scene.objects) {
        metrics::RigidMotion m;
        const ShapeDesc& s = o.shape;
        for (int a = 0; a < 3; ++a)
          m.centre[std::size_t(a)] = s.type == ShapeType::box
                                         ? 0.5 * (s.min[std::size_t(a)] + s.max[std::size_t(a)])
                                         : s.center[std::size_t(a)];
        m.velocity = o.velocity;
        m.omega = o.angular_velocity;
        motions.push_back(m);
      }
      r.rigid = metrics::rigid_motion_distance(frames, motions);
    }
    const std::size_t ref = plan.runs[i].reference;
    const std::string ref_dir = run_dir(out_dir, plan.runs[ref]);
    if (!record_complete(ref_dir)) continue;
    auto it = reference_frames.find(ref);
    if (it == reference_frames.end())
      it = reference_frames.emplace(ref, read_frames(ref_dir)).first;
    r.ref = metrics::reference_distance(frames, it->second);
  }
  return results;
}

namespace {

// The run's scheme with its parameter, "xpic(2)" (sim/mpm/schemes/scheme_label.hpp), or its solver
// method;
// "" when its scene cannot be read back.
std::string scheme_label_of(const PlannedRun& run) {
  try {
    return run_label(scene_of(run));
  } catch (const std::exception&) {
    return "";
  }
}

}  // namespace

std::string write_runs_csv(const Spec& spec, const std::vector<RunResult>& results,
                           const std::string& out_dir) {
  const std::string path = (std::filesystem::path(out_dir) / "runs.csv").string();
  std::ostringstream out;  // written whole (app/output_file.hpp)
  const std::vector<std::string> axes = spec.axis_keys();
  out << "id";
  for (const std::string& k : axes) out << ',' << k;
  out << ",dx,dt,particles,steps,step_wall_s,total_wall_s,cpu_s,particle_steps_per_s,"
         "newton_iters,cg_iters,peak_rss_mb,outcome,fail_step,fail_t,fail_quantity,"
         "unconverged_steps,noise,max_energy,final_energy,max_angular,final_angular,"
         "angular_relative,max_momentum,final_momentum,err_com,err_kinetic,err_elastic,"
         "err_displacement,displacement_rms,err_rigid,reference,scheme_label,energy_relative\n";
  for (const RunResult& r : results) {
    const PlannedRun& p = *r.run;
    const RunRecord& c = r.rec;
    auto num = [&](double v) { return r.present ? number_text(v, 6) : std::string(); };
    out << p.id;
    for (const std::string& k : axes) out << ',' << csv_field(p.value_text(k));
    out << ',' << number_text(p.dx, 6) << ',' << (p.dt > 0 ? number_text(p.dt, 6) : "") << ','
        << num(double(c.particles)) << ',' << num(double(c.steps)) << ',' << num(c.step_wall_s)
        << ',' << num(c.total_wall_s) << ',' << num(c.cpu_s) << ','
        << num(double(c.particles) * double(c.steps) / std::max(c.step_wall_s, 1e-9)) << ','
        << num(c.newton_iters) << ',' << num(c.cg_iters) << ',' << num(c.peak_rss_mb) << ','
        << r.outcome << ',' << (c.blew_up ? std::to_string(c.fail_step) : "") << ','
        << (c.blew_up ? number_text(c.fail_t, 6) : "") << ',' << csv_field(c.fail_quantity) << ','
        << num(double(c.unconverged_steps)) << ',' << num(c.noise) << ','
        << num(c.conservation.max_energy) << ',' << num(c.conservation.final_energy) << ','
        << num(c.conservation.max_angular) << ',' << num(c.conservation.final_angular) << ','
        << (r.present ? (c.conservation.angular_relative ? "1" : "0") : "") << ','
        << num(c.conservation.max_momentum) << ',' << num(c.conservation.final_momentum) << ','
        << number_text(r.ref.com, 6) << ',' << number_text(r.ref.kinetic, 6) << ','
        << number_text(r.ref.elastic, 6) << ',' << number_text(r.ref.displacement, 6) << ','
        << number_text(r.ref.displacement_rms, 6) << ',' << number_text(r.rigid, 6) << ','
        << results[p.reference].run->id << ',' << csv_field(scheme_label_of(p)) << ','
        << (r.present ? (c.conservation.energy_relative ? "1" : "0") : "") << '\n';
  }
  write_file_whole(path, out.str());
  return path;
}

std::vector<std::size_t> pareto_front(const std::vector<RunResult>& results,
                                      const std::string& error, const std::string& scene) {
  std::vector<std::size_t> candidates;
  for (std::size_t i = 0; i < results.size(); ++i) {
    const RunResult& r = results[i];
    if (!scene.empty() && r.run->value_text("scene") != scene) continue;
    if (r.run->reference == i) continue;  // its error is 0 by definition
    if ((r.outcome == "completed" || r.outcome == "noisy") && std::isfinite(r.error(error)) &&
        r.cost() > 0)
      candidates.push_back(i);
  }
  std::sort(candidates.begin(), candidates.end(), [&](std::size_t a, std::size_t b) {
    return results[a].cost() < results[b].cost() ||
           (results[a].cost() == results[b].cost() &&
            results[a].error(error) < results[b].error(error));
  });
  std::vector<std::size_t> front;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i : candidates)
    if (results[i].error(error) < best) {
      best = results[i].error(error);
      front.push_back(i);
    }
  return front;
}

}  // namespace apiclab::sweep
