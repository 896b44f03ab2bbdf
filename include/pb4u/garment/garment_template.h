#pragma once
// Built-in garments, defined once as continuous surfaces around a mannequin's bind pose and
// remeshed to any triangle count, so every resolution has the same shape.
//
// A template is the level set {field = 0} of field = body_field - gap (optionally united with
// a flared elliptic cone for skirts and dresses, smoothly), polygonised finely and cut along smooth
// scalar functions (hem, neckline, sleeve ends); the largest piece is kept. Because the body
// field is 1-Lipschitz the surface is at least `gap` from the body everywhere.
#include <string>
#include <vector>

#include "pb4u/body/body.h"
#include "pb4u/body/mannequin.h"
#include "pb4u/garment/skin_weight_transfer.h"
#include "pb4u/config/config_io.h"
#include "pb4u/garment/garment.h"

namespace pb4u {

// "tshirt", "tank_top", "long_sleeve", "long_dress", "skirt".
const std::vector<std::string>& garment_template_names();

struct GarmentTemplateConfig {
  double gap = 0.006;         // m, distance between body and garment at rest
  double cell_size = 0.006;   // m, polygonisation grid spacing of the template surface
  // Lengths along the arm (upper arm + forearm) from the shoulder joint, as fractions.
  double tshirt_sleeve = 0.3, long_sleeve = 0.9, sleeveless = -0.02;
  double sleeve_cut_radius = 0.05;  // fraction of stature: radius of the region a sleeve cut removes
  double neck_hole_radius = 0.058;        // fraction of stature: sleeved tops
  double scoop_neck_hole_radius = 0.068;  // fraction of stature: tank top and dress
  double neck_cut_height = 0.15;    // above the chest joint, fraction of the torso length
  double shirt_hem = -0.15;         // above the root joint, fraction of the torso length
  double skirt_top = 0.25;          // waistband above the root joint, fraction of the torso length
  double skirt_hem = 0.15;          // above the knee, fraction of the thigh length
  double dress_hem = -0.5;          // above the knee, fraction of the shin length
  double flare_x = 0.32, flare_z = 0.22;  // cone widening per metre of drop
  // At the waistband, fractions of stature; inside the waist so the band hugs the body.
  double cone_half_width = 0.07, cone_half_depth = 0.045;
  double cone_blend = 0.05;  // m: fillet between cone and body (a crease would need fine levels)
  // Skinning weights (garment_skin_weights), templates and garment files alike: nearest body
  // vertex within skin_inpaint_distance m of the body, inpainted farther out, smoothed over
  // skin_smoothing m. Both 0: raw nearest-vertex weights.
  double skin_smoothing = 0.1;
  double skin_inpaint_distance = 0.03;
  // m: every level's rest mesh, templates and garment files alike, at least this far from the
  // body at its bind pose, edges included (garment/clear_of_body.h); 0: as remeshed. Below the
  // template's gap, so a level whose chords clear the body is kept exactly as remeshed.
  double rest_clearance = 0.003;

  SkinWeightOptions skin_weight_options() const { return {skin_smoothing, skin_inpaint_distance}; }

  template <class V>
  void visit(V& v) {
    v("gap", gap, in_range(1e-4, 0.05));
    v("cell_size", cell_size, in_range(1e-3, 0.05));
    v("tshirt_sleeve", tshirt_sleeve, in_range(-0.2, 1.0));
    v("long_sleeve", long_sleeve, in_range(-0.2, 1.0));
    v("sleeveless", sleeveless, in_range(-0.2, 1.0));
    v("sleeve_cut_radius", sleeve_cut_radius, in_range(0.0, 0.2));
    v("neck_hole_radius", neck_hole_radius, in_range(0.0, 0.2));
    v("scoop_neck_hole_radius", scoop_neck_hole_radius, in_range(0.0, 0.2));
    v("neck_cut_height", neck_cut_height, in_range(-1.0, 1.0));
    v("shirt_hem", shirt_hem, in_range(-1.0, 1.0));
    v("skirt_top", skirt_top, in_range(-1.0, 1.0));
    v("skirt_hem", skirt_hem, in_range(-1.0, 1.0));
    v("dress_hem", dress_hem, in_range(-1.0, 1.0));
    v("flare_x", flare_x, in_range(0.0, 3.0));
    v("flare_z", flare_z, in_range(0.0, 3.0));
    v("cone_half_width", cone_half_width, in_range(0.01, 0.5));
    v("cone_half_depth", cone_half_depth, in_range(0.01, 0.5));
    v("cone_blend", cone_blend, in_range(0.0, 0.3));
    v("skin_smoothing", skin_smoothing, in_range(0.0, 1.0));
    v("skin_inpaint_distance", skin_inpaint_distance, in_range(0.0, 1.0));
    v("rest_clearance", rest_clearance, in_range(0.0, 0.05));
  }
};

// The template's fine surface (the shape every level is remeshed from), around `body`'s
// bind pose. `mannequin` must be the config the body was built with. Throws pb4u::Error on
// an unknown template name.
TriMesh garment_template_surface(const std::string& name, const Body& body,
                                 const MannequinConfig& mannequin,
                                 const GarmentTemplateConfig& config = {});

// A template remeshed to about `target_triangles`, with weights from `body`
// (garment_skin_weights with `skin_smoothing` m).
Garment make_garment(const std::string& name, const TriMesh& surface, const Body& body,
                     int target_triangles,
                     const SkinWeightOptions& skin = GarmentTemplateConfig{}.skin_weight_options());

}  // namespace pb4u
