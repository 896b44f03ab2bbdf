// `pb4u simulate --checkpoint P --scene S --out DIR [--method net|reference] [--frames N]`.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <iostream>
#include <optional>

#include "pb4u/cli/commands.h"
#include "pb4u/sim/simulate.h"
#include "pb4u/util/device.h"
#include "pb4u/util/error.h"

namespace pb4u {

void add_simulate_command(CLI::App& app, const GlobalOptions& global) {
  auto* cmd = app.add_subcommand(
      "simulate",
      "Roll a scene (configs/scenes/*.yaml) out with the network or the reference solver and\n"
      "write per-frame garment/body meshes (OBJ or PLY), PC2 point caches (Blender: Mesh Cache\n"
      "modifier on garment_0000.obj), garment_rest.obj, rollout.h5, energies.csv, energies.png\n"
      "and preview.png (a contact sheet: front and side views, vertices inside the body in red).\n"
      "Ends with a one-line summary: positive energy, share inside the body, time per frame.");
  struct Args {
    std::string device = "cpu";
    std::string checkpoint, scene, out, method = "net", format, preview;
    int frames = 0, refine = -1, minimum_every = -1;
    double refine_tolerance = -1;
    std::vector<std::string> sets;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("--checkpoint", args->checkpoint, "Training checkpoint or export (needed for --method net)");
  cmd->add_option("--scene,-s", args->scene, "Scene YAML")->required();
  cmd->add_option("--out,-o", args->out, "Output directory")->required();
  cmd->add_option("--method", args->method,
                  "net | reference (the solver with the scene's physics.solver.contact: by default barrier, "
                  "intersection-free contact with SPEC 3.3's penalty kept beside it) | penalty (the solver with "
                  "the penalty term alone, which lets cloth sit inside the body)")
      ->check(CLI::IsMember({"net", "reference", "penalty"}));
  cmd->add_option("--frames", args->frames, "Frames to simulate (overrides the scene's)")->check(CLI::PositiveNumber);
  cmd->add_option("--format", args->format, "Per-frame meshes: obj | ply | none (overrides the scene's)")
      ->check(CLI::IsMember({"obj", "ply", "none"}));
  cmd->add_option("--preview", args->preview, "preview.png contact sheet: on | off (overrides the scene's)")
      ->check(CLI::IsMember({"on", "off"}));
  cmd->add_option("--refine", args->refine,
                  "Refine each network step by N iterations of the reference solver (physics.solver; with "
                  "barrier contact, the default, the step is made intersection-free first); 0: off (scene key "
                  "refine.iterations)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--refine-tolerance", args->refine_tolerance,
                  "Refine each network step until the solver's step is below MM millimetres; with --refine N, "
                  "at most N iterations first (fewer where the step is below MM already), then on until below MM "
                  "(scene key refine.tolerance_mm)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--minimum-every", args->minimum_every,
                  "Every N-th frame, solve the frame's step on to the energy's minimum (to 0.001 mm) and write "
                  "energies.csv's distance_to_minimum_mm and energy_gap_j: what the residual estimates, measured; "
                  "a reference solve per sampled frame; 0: off (scene key outputs.minimum_every)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--set", args->sets, "Override a scene key, e.g. --set material.mu=30000 (repeatable)");
  cmd->add_option("--device", args->device, "Where the network runs: cpu | cuda | cuda:N (metrics stay on the CPU)");
  cmd->callback([args, &global] {
    apply_global_options(global);
    std::vector<std::string> sets = args->sets;
    if (args->frames > 0) sets.push_back("frames=" + std::to_string(args->frames));
    if (args->refine >= 0) sets.push_back("refine.iterations=" + std::to_string(args->refine));
    if (args->method == "penalty") sets.push_back("physics.solver.contact=penalty");
    if (args->refine_tolerance >= 0) sets.push_back(fmt::format("refine.tolerance_mm={}", args->refine_tolerance));
    if (args->minimum_every >= 0) sets.push_back("outputs.minimum_every=" + std::to_string(args->minimum_every));
    if (!args->format.empty()) sets.push_back("outputs.mesh_format=" + args->format);
    if (!args->preview.empty()) sets.push_back(std::string("outputs.preview=") + (args->preview == "on" ? "true" : "false"));
    const SceneConfig scene = load_config<SceneConfig>(args->scene, sets);
    std::optional<ModelFile> model;
    if (args->method != "net" && scene.refine.enabled())
      throw Error("--refine: refines the network's step; use it with --method net");
    if (args->method == "net") {
      if (args->checkpoint.empty()) throw Error("--checkpoint: required with --method net");
      model = load_model_file(args->checkpoint);
      model->model->to(resolve_device(args->device, "--device"));
    }
    SimulateResult r = simulate(scene, args->scene, model ? &*model : nullptr, args->out);
    std::string inside;
    if (r.with_body)
      inside = fmt::format("; inside the body mean {:.2f}%, max {:.2f}% (deepest {:.1f} mm), cloth edges through it "
                           "on {} frames (at most {})",
                           100 * r.penetrating_mean, 100 * r.penetrating_max, r.deepest_mm, r.edges_through_frames,
                           r.edges_through_max);
    if (r.body_self_crossing_frames > 0)
      inside += fmt::format("; the body crosses itself on {} frames (at most {} of its faces inside another part)",
                            r.body_self_crossing_frames, r.body_self_crossing_max);
    if (r.own_start_frames > 0)
      inside += fmt::format("; on {} frames the refinement started from the solver's own start instead of the "
                            "network's step (higher in the solver's objective, or leaving cloth with no free place)",
                            r.own_start_frames);
    if (r.barrier_contact)
      inside += fmt::format("; {} frames left cloth out of barrier contact (at most {} vertices)", r.excluded_frames,
                            r.excluded_max);
    const std::string residual = r.residual_measured ? fmt::format("residual median {:.3g} mm, mean {:.3g} mm, max {:.3g} mm",
                                                                   r.residual_mm_median, r.residual_mm_mean,
                                                                   r.residual_mm_max)
                                                     : std::string("residual not measured (outputs.residual off)");
    std::string minimum;
    if (r.minimum.frames > 0)
      minimum = fmt::format("; distance to the minimum on {} sampled frames median {:.3g} mm, max {:.3g} mm "
                            "(energy gap median {:.3g} J)",
                            r.minimum.frames, r.minimum.distance_median_mm, r.minimum.distance_max_mm,
                            r.minimum.gap_median_j);
    spdlog::info("{} frames: positive energy mean {:.4g} J, max {:.4g} J{}; {}{}; {:.1f} ms per frame ({}); {} files in {}",
                 r.frames - 1, r.positive_mean, r.positive_max, inside, residual, minimum, r.step_ms_mean,
                 model ? (scene.refine.enabled() || model->config.refines() ? "network step + refinement"
                                                                                       : "network step")
                       : "solver step",
                 r.files.size(), args->out);
    if (r.diverged)
      throw Error(args->scene + ": diverged at frame " + std::to_string(r.diverged_at_frame) + ": " +
                  r.diverged_reason + " (vertex " + std::to_string(r.worst_vertex) +
                  " non-finite or moved most); frames 0-" + std::to_string(r.frames - 1) + " are written to " +
                  args->out);
  });
}

}  // namespace pb4u
