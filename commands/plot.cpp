// `plot`: pictures of the model, drawn off-screen into PNG files.
//
// Items are keywords that may all appear in one command, each with an optional quantity
// after it, so pictures layer the way people say them: `plot block disp vector vel`.
// Whatever order they are typed in, they are drawn blocks first, then zones, contacts,
// principal stresses and vectors, because each later layer needs to see through the earlier
// ones (the builder makes blocks translucent under arrows; this file does the same under
// contacts, which lie on faces the blocks share, and zones under principal stresses).
// `history` draws a chart, which is a picture of its own and takes no 3D items.
//
// Zones are selected apart from blocks: a range keeps the zones whose centroid it contains
// (as `insitu` does), so `plot zone szz range z 0 5` shows a slab of a block whose centroid
// lies outside the slab. `principal` draws the zones' principal stresses when the model has
// zones, the contacts' otherwise.
#include "commands.h"
#include "engine/flow.h"
#include "common.h"
#include "plot_settings.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "engine/blocks.h"
#include "render/contact_bridge.h"
#include "render/scene_builder.h"
#include "render/vtk_backend.h"

namespace odec {

namespace {

using render::BlockColour;
using render::ContactQuantity;
using render::VectorKind;

const std::vector<std::string> kBlockQuantities = {"disp", "xdis", "ydis",  "zdis",     "vel",    "xvel",
                                                   "yvel", "zvel", "group", "material", "region", "fixed"};
const std::vector<std::string> kContactQuantities = {"nstress", "sstress", "ndis", "sdis", "state", "pp", "aperture"};
const std::vector<std::string> kZoneQuantities = {"sxx", "syy",  "szz",  "sxy",   "sxz", "syz",
                                                  "smin", "smid", "smax", "state", "disp"};
const std::vector<std::string> kViews = {"iso", "x", "-x", "y", "-y", "z", "-z", "eye"};
const std::vector<std::string> kBackgrounds = {"white", "black", "grey"};
const std::vector<std::string> kMaps = {"auto", "rainbow", "coolwarm", "viridis", "grey"};

BlockColour block_colour(const std::string& q) {
    static const std::map<std::string, BlockColour> table = {
        {"disp", BlockColour::Disp},   {"xdis", BlockColour::XDis},         {"ydis", BlockColour::YDis},
        {"zdis", BlockColour::ZDis},   {"vel", BlockColour::Vel},           {"xvel", BlockColour::XVel},
        {"yvel", BlockColour::YVel},   {"zvel", BlockColour::ZVel},         {"group", BlockColour::Group},
        {"material", BlockColour::Material}, {"region", BlockColour::Region}, {"fixed", BlockColour::Fixed}};
    return table.at(q);
}

ContactQuantity contact_quantity(const std::string& q) {
    static const std::map<std::string, ContactQuantity> table = {
        {"nstress", ContactQuantity::NormalStress}, {"sstress", ContactQuantity::ShearStress},
        {"ndis", ContactQuantity::NormalDisp},      {"sdis", ContactQuantity::ShearDisp},
        {"state", ContactQuantity::State}, {"pp", ContactQuantity::PorePressure},
        {"aperture", ContactQuantity::Aperture}};
    return table.at(q);
}

render::ZoneQuantity zone_quantity(const std::string& q) {
    using render::ZoneQuantity;
    static const std::map<std::string, ZoneQuantity> table = {
        {"sxx", ZoneQuantity::SXX},   {"syy", ZoneQuantity::SYY},     {"szz", ZoneQuantity::SZZ},
        {"sxy", ZoneQuantity::SXY},   {"sxz", ZoneQuantity::SXZ},     {"syz", ZoneQuantity::SYZ},
        {"smin", ZoneQuantity::SMin}, {"smid", ZoneQuantity::SMid},   {"smax", ZoneQuantity::SMax},
        {"state", ZoneQuantity::State}, {"disp", ZoneQuantity::Disp}};
    return table.at(q);
}

render::Rgb background_colour(const std::string& name) {
    if (name == "black") return {0, 0, 0};
    if (name == "grey") return {0.82, 0.82, 0.82};
    return {1, 1, 1};
}

std::optional<render::ColourMap> colour_map(const std::string& name) {
    if (name == "rainbow") return render::ColourMap::Rainbow;
    if (name == "coolwarm") return render::ColourMap::CoolWarm;
    if (name == "viridis") return render::ColourMap::Viridis;
    if (name == "grey") return render::ColourMap::Grey;
    return std::nullopt;
}

// The quantity given after an item keyword, or its default.
std::string quantity_of(const KeywordUse& u, const std::string& fallback) {
    return u.values.empty() ? fallback : u.values[0].text;
}

// `view ...` of this command into the settings' form, checked.
void read_view(const Args& a, std::string& view, Vec3& eye) {
    const KeywordUse* u = a.find("view");
    view = u->values[0].text;
    if (view == "eye") {
        if (u->values.size() < 2) {
            fail(u->values[0].loc, "'view eye' needs the eye point x,y,z", {"for example: view eye 10,-20,8"}, "plot");
        }
        eye = u->values[1].vec;
    } else if (u->values.size() > 1) {
        fail(u->values[1].loc, "a point goes with 'view eye' only", {"write 'view eye x,y,z' to look from a point"},
             "plot");
    }
}

std::string settings_text(const PlotSettings& s) {
    std::string view = s.view == "eye" ? "eye " + vec_text(s.eye) : s.view;
    return "size " + std::to_string(s.width) + " " + std::to_string(s.height) + ", view " + view + ", background " +
           s.background + ", map " + s.map;
}

// `plot set ...`: store defaults, draw nothing.
void store_settings(CommandContext& ctx, const Args& a, PlotSettings& settings) {
    for (const KeywordUse& u : a.uses) {
        const std::string& k = u.spec->name;
        if (k != "set" && k != "size" && k != "view" && k != "background" && k != "map") {
            fail(u.loc, "'" + k + "' cannot go with 'set'",
                 {"'plot set' keeps size, view, background and map for later plots and draws nothing"}, "plot");
        }
    }
    PlotSettings next = settings;
    if (a.has("size")) {
        next.width = a.integer("size", 0);
        next.height = a.integer("size", 1);
    }
    if (a.has("view")) {
        read_view(a, next.view, next.eye);
        next.view_set = true;
    }
    if (a.has("background")) next.background = a.text("background");
    if (a.has("map")) next.map = a.text("map");
    settings = next;
    if (!ctx.interp.quiet) ctx.out << "plot defaults: " << settings_text(settings) << "\n";
}

// Centre of the shown blocks' bounding box: where a cut goes when no origin is given.
Vec3 blocks_centre(const Model& m, const std::vector<int>& blocks) {
    Eigen::AlignedBox3d box;
    for (int b : blocks) {
        const Polyhedron p = world_shape(m, b);
        for (const Vec3& v : p.vertices) box.extend(v);
    }
    return box.isEmpty() ? Vec3::Zero() : Vec3(box.center());
}

bool block_shown(const Model& m, int b) { return (m.blocks.flags[b] & (kHidden | kExcavated)) == 0; }

// Centre of the bounding box of these zones: where a cut goes in a picture of zones alone.
Vec3 zones_centre(const Model& m, const std::vector<int>& zones) {
    Eigen::AlignedBox3d box;
    for (int z : zones)
        for (int g : m.zones.gp[z]) box.extend(m.gridpoints.pos[g]);
    return box.isEmpty() ? Vec3::Zero() : Vec3(box.center());
}

// Where the picture goes: the file given (".png" added when it has no extension), or the
// next free plot-NNNN.png in the working directory. Checked before anything is drawn.
std::string picture_path(const CommandContext& ctx, const Args& a) {
    namespace fs = std::filesystem;
    if (!a.has("file")) {
        int last = 0;
        std::error_code ec;
        for (const auto& entry : fs::directory_iterator(".", ec)) {
            const std::string name = entry.path().filename().string();
            // plot-NNNN.png: four or more digits.
            if (name.size() < 13 || name.size() > 18 || name.compare(0, 5, "plot-") != 0 ||
                name.compare(name.size() - 4, 4, ".png") != 0)
                continue;
            const std::string digits = name.substr(5, name.size() - 9);
            if (digits.find_first_not_of("0123456789") != std::string::npos) continue;
            last = std::max(last, std::stoi(digits));
        }
        char buf[32];
        std::snprintf(buf, sizeof buf, "plot-%04d.png", last + 1);
        if (access(".", W_OK) != 0) {
            fail(a.loc, "cannot write '" + std::string(buf) + "': the working directory is not writable",
                 {"give a file in a writable directory: plot ... file '/tmp/picture.png'"}, "plot");
        }
        return buf;
    }
    const Value& v = a.find("file")->values[0];
    check_file_allowed(ctx, v.loc, v.text, "plot");
    fs::path path(v.text);
    std::string ext = path.extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext.empty()) {
        path += ".png";
    } else if (ext != ".png") {
        fail(v.loc, "pictures are PNG files: '" + v.text + "' should end in '.png'", {}, "plot");
    }
    const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) {
        fail(v.loc, "cannot write '" + path.string() + "': there is no directory '" + dir.string() + "'", {}, "plot");
    }
    if (access(dir.c_str(), W_OK) != 0) {
        fail(v.loc, "cannot write '" + path.string() + "': the directory '" + dir.string() + "' is not writable", {},
             "plot");
    }
    return path.string();
}

// Contacts the range keeps (all, when there is none), skipping those of hidden blocks.
std::vector<int> contacts_in_range(const Model& m, const Args& a) {
    std::vector<int> out;
    const ContactSet& cs = m.contacts;
    for (int c = 0; c < cs.size(); ++c) {
        const int ba = cs.block_a[c], bb = cs.block_b[c];
        if (!block_shown(m, ba) || !block_shown(m, bb)) continue;
        if (a.has_range && !a.range.contains_contact(m, contact_centroid(m, c), ba, bb)) continue;
        out.push_back(c);
    }
    return out;
}

// A sub-contact's point is a corner of the contact polygon, and its share of the area lies
// between that corner and the contact's centroid. A patch drawn at the corner would hang
// over the blocks' edges; drawn halfway, the patches of a rectangular contact tile it.
void centre_sub_contacts(ContactView& view) {
    ContactRows& subs = view.sub_contacts;
    for (int i = 0; i < subs.size(); ++i) {
        subs.centroid[i] = 0.5 * (subs.centroid[i] + view.contacts.centroid[subs.parent[i]]);
    }
}

std::string ms_text(double ms) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.0f ms", ms);
    return buf;
}

using Clock = std::chrono::steady_clock;

// Draw the scene and say where it went (and, with echo on, how long it took: the scene
// from the model, then VTK's part, so a slow picture shows which half to look at).
void draw(CommandContext& ctx, const Args& a, const render::Scene& scene, const std::string& path,
          Clock::time_point t0) {
    const auto t1 = Clock::now();
    std::string error;
    if (!render::render_png(scene, path, error)) {
        fail(a.has("file") ? a.find("file")->values[0].loc : a.loc, error, {}, "plot");
    }
    if (ctx.interp.quiet) return;
    ctx.out << "plot: wrote " << path;
    if (ctx.interp.echo) {
        const double scene_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
        const render::RenderTimes rt = render::last_render_times();
        ctx.out << " in " << ms_text(scene_ms + rt.total_ms) << " (scene " << ms_text(scene_ms) << ", render "
                << ms_text(rt.total_ms);
        // The first picture of a session also starts the renderer: say so, or it looks slow.
        if (rt.context_ms > 0) ctx.out << ", of which " << ms_text(rt.context_ms) << " starting the renderer";
        ctx.out << ")";
    }
    ctx.out << "\n";
}

// 3DEC's plot views (`plot create`, `plot add ...`, `plot set projection ...`): odec draws a
// picture per command and keeps no view, so these are accepted with a warning. `plot bitmap
// ... filename f` draws the default picture into f. True when the command was one of them.
bool classic_plot_form(CommandContext& ctx, const Args& a) {
    static const char* const kClassic[] = {"create", "clear", "add", "reset", "current", "destroy", "bitmap", "projection"};
    const KeywordUse* use = nullptr;
    for (const char* k : kClassic) {
        if ((use = a.find(k))) break;
    }
    if (!use) return false;
    const std::string& k = use->spec->name;
    if (k == "bitmap") {
        std::string file;
        for (size_t i = 0; i + 1 < use->rest.size(); ++i) {
            if (use->rest[i].lower == "filename" || use->rest[i].lower == "file") file = use->rest[i + 1].text;
        }
        warn(ctx, use->loc, "'plot bitmap': odec keeps no plot views; it draws 'plot block' into " +
                                (file.empty() ? std::string("the next free plot-NNNN.png") : "'" + file + "'"));
        std::string cmd = "plot block";
        if (!file.empty()) {
            if (file.find('\'') != std::string::npos) fail(use->loc, "'plot bitmap': a file name with a quote", {}, "plot");
            cmd += " file '" + file + "'";
        }
        // Drawn as the command the warning names.
        const std::string where = use->loc.file ? use->loc.file->name : std::string("<input>");
        if (!ctx.interp.run_text(where + " (plot bitmap)", cmd, false)) throw ScriptFailed{};
        return true;
    }
    warn(ctx, use->loc, "'plot " + k + " ...' (a 3DEC plot view) is accepted and ignored: each 'plot' command draws "
                        "a picture of its own");
    return true;
}

void handle_plot(CommandContext& ctx, const Args& a) {
    const auto t0 = Clock::now();
    const Model& m = ctx.model;
    PlotSettings& settings = plot_settings(ctx.interp);
    if (classic_plot_form(ctx, a)) return;
    if (const KeywordUse* axes = a.find("axes")) {
        warn(ctx, axes->loc, "'axes ...' is not drawn by odec: the picture shows the axes' directions in its title");
    }
    if (const KeywordUse* ax = a.has("xaxis") ? a.find("xaxis") : a.find("yaxis")) {
        warn(ctx, ax->loc, "axis labels ('xaxis ...', 'yaxis ...') are ignored: a history chart is labelled by the "
                           "histories' own labels ('hist label n text')");
    }
    if (a.has("set")) {
        store_settings(ctx, a, settings);
        return;
    }

    const KeywordUse* block = a.find("block");
    const KeywordUse* vector = a.find("vector");
    const KeywordUse* principal = a.find("principal");
    const KeywordUse* contact = a.find("contact");
    const KeywordUse* zone = a.find("zone");
    const KeywordUse* history = a.find("history");
    const KeywordUse* cable = a.find("cable");
    const KeywordUse* liner = a.find("liner");
    const bool any_3d = block || vector || principal || contact || zone || cable || liner;
    if (a.has("vs") && !history) fail(a.find("vs")->loc, "'vs' goes with 'history'", {}, "plot");
    if (history) {
        for (const KeywordUse& u : a.uses) {
            const std::string& k = u.spec->name;
            if (k == "block" || k == "vector" || k == "principal" || k == "contact" || k == "zone" || k == "cable" || k == "liner" || k == "cut" ||
                k == "range" || k == "view" || k == "map" || k == "scale" || k == "ids" || k == "magnify") {
                fail(u.loc, "'" + k + "' cannot go with 'history'",
                     {"a history chart is a picture of its own: plot it with a separate 'plot' command"}, "plot");
            }
        }
    }

    // Options: the stored defaults, then what this command says.
    render::PlotOptions opt;
    opt.width = a.has("size") ? a.integer("size", 0) : settings.width;
    opt.height = a.has("size") ? a.integer("size", 1) : settings.height;
    std::string view = settings.view;
    Vec3 eye = settings.eye;
    if (a.has("view")) read_view(a, view, eye);
    if (view == "eye") opt.camera = render::camera_for_eye(eye);
    else render::camera_for_view(view, opt.camera);
    opt.view_given = a.has("view") || settings.view_set;
    opt.ids = a.has("ids");
    opt.background = background_colour(a.has("background") ? a.text("background") : settings.background);
    opt.map = colour_map(a.has("map") ? a.text("map") : settings.map);
    if (a.has("scale")) {
        const double lo = a.real("scale", 0), hi = a.real("scale", 1);
        if (!(hi > lo)) {
            fail(a.find("scale")->values[1].loc, "'scale' hi must be greater than lo (got " + num(lo) + " and " +
                                                     num(hi) + ")",
                 {}, "plot");
        }
        opt.limits = std::make_pair(lo, hi);
    }
    if (a.has("magnify")) opt.magnify = a.real("magnify");

    render::Scene scene;
    if (history) {
        std::vector<int> numbers;
        for (const Value& v : history->values) numbers.push_back(history_number(m, v, "plot"));
        const int vs = a.has("vs") ? history_number(m, a.find("vs")->values[0], "plot") : 0;
        if (m.histories.sample_steps.empty()) {
            fail(history->loc, "the histories have no samples yet", {"take some steps first"}, "plot");
        }
        for (size_t k = 0; k < numbers.size(); ++k) {
            // Made since the last sample: its own samples start with the next one.
            if (m.histories.items[numbers[k] - 1].values.empty()) {
                warn(ctx, history->values[k].loc,
                     "history " + std::to_string(numbers[k]) + " has no samples yet: it is left out of the chart");
            }
        }
        const std::string path = picture_path(ctx, a);
        scene = render::begin_scene(m, opt);
        std::string error;
        if (!render::add_history_chart(scene, m.histories, numbers, vs, error)) fail(history->loc, error, {}, "plot");
        draw(ctx, a, scene, path, t0);
        return;
    }

    // 3D items; `plot` alone is `plot block disp`.
    std::vector<int> blocks = a.has_range ? select_blocks(m, a.range) : std::vector<int>{};
    if (!a.has_range) {
        for (int b = 0; b < m.blocks.size(); ++b) blocks.push_back(b);
    }
    blocks.erase(std::remove_if(blocks.begin(), blocks.end(), [&](int b) { return !block_shown(m, b); }),
                 blocks.end());
    // Zones: those of the shown blocks, and of them those the range keeps by their centroid.
    // 'principal' draws zones when the range keeps some, else the contacts it keeps.
    const std::vector<int> all_zones = render::zones_to_draw(m, render::PlotOptions());
    std::vector<int> zones;
    for (int z : all_zones) {
        if (!a.has_range || a.range.contains_point(m, zone_centroid(m, z), m.zones.block[z])) zones.push_back(z);
    }
    const bool zone_principal = principal && !zones.empty();
    if (zone && all_zones.empty() && m.zones.size() > 0) {
        fail(zone->loc, "there are no zones to plot: their blocks are hidden or excavated, or the zones null",
             {"'seek' shows hidden blocks again"}, "plot");
    }
    if (zone && all_zones.empty()) {
        fail(zone->loc, "there are no zones to plot: 'zone' draws the zones of deformable blocks",
             {"divide blocks into zones with 'gen edge e'"}, "plot");
    }
    const bool range_misses_zones = !all_zones.empty() && zones.empty();
    if (cable && m.cables.size() == 0) {
        fail(cable->loc, "there are no cables to plot", {"make one with 'cable x1,y1,z1 x2,y2,z2 seg n prop p'"}, "plot");
    }
    if (liner && m.liners.size() == 0) {
        fail(liner->loc, "there are no liners to plot", {"lay one with 'liner range ... prop n'"}, "plot");
    }
    if (range_misses_zones && zone) fail(a.range_loc, "the range selects no zones to plot", {"widen the range"}, "plot");
    if (range_misses_zones && principal && !contact && contacts_in_range(m, a).empty()) {
        fail(a.range_loc, "the range selects no zones or contacts for 'principal'", {"widen the range"}, "plot");
    }
    if (zone || zone_principal) {
        if (a.has_range) opt.zones = zones;
        opt.zone_item = zone != nullptr;
    } else {
        zones.clear();
    }
    const bool needs_blocks = block || vector || contact || (principal && !zone_principal) || !any_3d;
    if (blocks.empty() && (needs_blocks || zones.empty())) {
        const SourceLoc& where = a.has_range ? a.range_loc : a.loc;
        if (a.has_range && m.blocks.size() > 0) fail(where, "the range selects no blocks to plot", {}, "plot");
        fail(where, "there are no blocks to plot", {"make blocks first, e.g. 'poly brick 0 1 0 1 0 1'"}, "plot");
    }
    if (a.has_range) opt.blocks = blocks;

    if (a.has("cut")) {
        const KeywordUse* u = a.find("cut");
        const double dip = u->values[1].number * M_PI / 180.0, dd = u->values[2].number * M_PI / 180.0;
        render::CutPlane cut;
        // The plane's upward normal (language.md): what lies above is cut away.
        cut.normal = Vec3(std::sin(dip) * std::sin(dd), std::sin(dip) * std::cos(dd), std::cos(dip));
        cut.origin = u->values.size() > 3 ? u->values[3].vec
                     : blocks.empty()     ? zones_centre(m, zones)
                                          : blocks_centre(m, blocks);
        opt.cut = cut;
    }

    ContactView contacts;
    if (contact || (principal && !zone_principal)) {
        const std::vector<int> chosen = contacts_in_range(m, a);
        if (chosen.empty()) {
            fail((contact ? contact : principal)->loc,
                 m.contacts.size() == 0 ? "there are no contacts to plot" : "the range selects no contacts to plot",
                 {m.contacts.size() == 0 ? "contacts are found when the model steps: take a step first"
                                         : "widen the range"},
                 "plot");
        }
        if (ctx.model.flow.configured && ctx.model.contacts.detected) {
            flow_sync(ctx.model);
            flow_apertures(ctx.model);
        }
        contacts = make_contact_view(m, &chosen);
        centre_sub_contacts(contacts);
    }
    const std::string path = picture_path(ctx, a);

    scene = render::begin_scene(m, opt);
    if (block || !any_3d) {
        render::add_blocks(scene, m, block_colour(block ? quantity_of(*block, "disp") : "disp"), opt);
    } else if (!zone) {
        render::add_block_outline(scene, m, opt);
    }
    if (zone) render::add_zones(scene, m, zone_quantity(quantity_of(*zone, "smin")), opt);
    std::string error;
    if (contact) {
        if (!render::add_contacts(scene, contacts, contact_quantity(quantity_of(*contact, "nstress")), opt, error)) {
            fail(contact->loc, error, {}, "plot");
        }
    }
    if (principal) {
        render::add_principal(scene, zone_principal ? render::principal_from_zones(m, opt)
                                                    : render::principal_from_contacts(contacts),
                              opt);
    }
    if ((contact || principal) && block) {
        // Contacts lie on faces the blocks share: see them through the blocks.
        for (auto& layer : scene.polygons) {
            if (layer.name == "blocks") layer.opacity = std::min(layer.opacity, 0.3);
        }
    }
    if (zone_principal && zone) {
        // Bars inside the zones: see them through the surface (on a section they lie on it),
        // and leave out the zone edges, which would hide the thinner bars.
        for (auto& layer : scene.polygons) {
            if (layer.name != "zones") continue;
            layer.edges = false;
            if (!opt.cut) layer.opacity = std::min(layer.opacity, 0.3);
        }
    }
    if (vector) render::add_vectors(scene, m, quantity_of(*vector, "disp") == "vel" ? VectorKind::Vel : VectorKind::Disp, opt);
    if (cable) {
        // Cables run inside the rock: see them through the blocks and zones.
        for (auto& layer : scene.polygons) {
            if (layer.name == "blocks" || layer.name == "zones") layer.opacity = std::min(layer.opacity, 0.3);
        }
        render::add_cables(scene, m, opt);
    }
    if (liner) {
        // Liners lie on the rock's surface: see them through the blocks and zones.
        for (auto& layer : scene.polygons) {
            if (layer.name == "blocks" || layer.name == "zones") layer.opacity = std::min(layer.opacity, 0.3);
        }
        render::add_liners(scene, m, opt);
    }

    draw(ctx, a, scene, path, t0);
}

} // namespace

PlotSettings& plot_settings(const Interpreter& interp) { return const_cast<Interpreter&>(interp).plot; }

const CommandSpec& plot_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("plot", 2, "draw a picture of the model into a PNG file, off-screen");
        c.keyword("block", 2, "blocks coloured by a quantity").one_of("quantity", kBlockQuantities).optional("disp");
        c.keyword("vector", 2, "arrows of displacement or velocity at block centroids and surface gridpoints")
            .one_of("quantity", {"disp", "vel"})
            .optional("disp");
        c.keyword("principal", 2, "principal-stress bars at the zones, or on the contacts when there are no zones");
        c.keyword("cable", 3, "cables as thin tubes coloured by their axial force (N, tension positive), through "
                              "translucent blocks");
        c.keyword("liner", 3, "liners as their triangles coloured by the membrane force n_x (N/m, tension positive; "
                              "a lining's thrust is -n_x), through translucent blocks");
        c.keyword("contact", 2, "contact patches coloured by a quantity")
            .one_of("quantity", kContactQuantities)
            .optional("nstress");
        c.keyword("zone", 2, "zones of deformable blocks coloured by a quantity (stresses in Pa, tension positive)")
            .one_of("quantity", kZoneQuantities)
            .optional("smin");
        c.keyword("magnify", 3, "draw displacements m times as large (deformed shape = original + m * disp)")
            .real("m", 0, 1e9)
            .defaults("1");
        c.keyword("history", 2, "a line chart of histories n ... against the step (a picture of its own)")
            .integer("n", 1)
            .repeat();
        c.keyword("vs", 1, "with 'history': history m along the horizontal axis instead of the step").integer("m", 1);
        c.keyword("file", 2, "the PNG file to write").string("name").defaults("the next free plot-NNNN.png");
        c.keyword("size", 2, "picture width and height, pixels")
            .integer("w", 16, 8192)
            .integer("h", 16, 8192)
            .defaults("1024 768");
        c.keyword("view", 2, "where the eye is: iso, on an axis (x, -x, ...), or at a point ('eye x,y,z')")
            .one_of("from", kViews)
            .vec("point")
            .optional()
            .defaults("iso");
        c.keyword("cut", 2, "a section: the part above the plane (dip, dip direction, through origin) is cut away")
            .one_of("shape", {"plane"})
            .real("dip", 0, 90)
            .labelled()
            .real("dd", 0, 360)
            .labelled()
            .vec("origin")
            .labelled()
            .optional("the centre of the blocks");
        c.keyword("map", 3, "colour map of continuous quantities").one_of("name", kMaps).defaults("auto");
        c.keyword("scale", 2, "fixed colour scale from lo to hi (default: the data's own range)").real("lo").real("hi");
        c.keyword("background", 2, "background colour").one_of("colour", kBackgrounds).defaults("white");
        c.keyword("ids", 3, "label each block drawn with its id (as 'range id' takes it)");
        c.keyword("set", 3, "keep this command's size, view, background and map for later plots; draw nothing");
        // 3DEC's plot views, accepted for its scripts (see classic_plot_form).
        c.keyword("create", 3, "(3DEC) create a plot view: accepted and ignored, with a warning").rest_as_words().in_choice(9);
        c.keyword("clear", 3, "(3DEC) clear the plot view: accepted and ignored").rest_as_words().in_choice(9);
        c.keyword("add", 3, "(3DEC) add an item to the plot view: accepted and ignored").rest_as_words().in_choice(9);
        c.keyword("reset", 3, "(3DEC) reset the plot view: accepted and ignored").rest_as_words().in_choice(9);
        c.keyword("current", 3, "(3DEC) choose the current plot view: accepted and ignored").rest_as_words().in_choice(9);
        c.keyword("destroy", 3, "(3DEC) delete a plot view: accepted and ignored").rest_as_words().in_choice(9);
        c.keyword("bitmap", 3, "(3DEC) write the plot view to 'filename f': draws 'plot block' into f").rest_as_words().in_choice(9);
        c.keyword("projection", 4, "(3DEC, after 'set') the view's projection and camera: accepted and ignored").rest_as_words().in_choice(9);
        c.keyword("axes", 3, "(3DEC) draw the axes: accepted and ignored").rest_as_words();
        c.keyword("xaxis", 3, "(3DEC) the chart's x axis title: accepted and ignored").rest_as_words();
        c.keyword("yaxis", 3, "(3DEC) the chart's y axis title: accepted and ignored").rest_as_words();
        c.range("which blocks (and the contacts between them, and the zones whose centroid it contains) to draw: see 'help range'");
        c.describe(
            "Items are 'block', 'zone', 'vector', 'principal', 'contact', 'cable' and 'liner', each but 'cable' and 'liner' with an "
            "optional quantity after it; several may be given and are layered in one picture (blocks, then zones, "
            "contacts, principal stresses, vectors and cables; blocks turn translucent under contacts, arrows and "
            "cables). 'cable' draws each cable segment as a thin tube coloured by its axial force; 'liner' each liner "
            "element coloured by its membrane force n_x. 'plot' alone "
            "is 'plot block disp'. Without 'block' or 'zone', the other items are drawn over the block edges. "
            "'history n ... [vs m]' draws a line chart instead, with 'file', 'size' and 'background' as its only "
            "options. "
            "Block quantities: disp, xdis, ydis, zdis (m), vel, xvel, yvel, zvel (m/s), group, material, region, "
            "fixed (free, fixed, or moving with a velocity given by 'bound': how the model is supported). A "
            "deformable block is drawn as the surface of its zones at its gridpoints, so its picture shows its "
            "deformed shape, and its displacements and velocities are those of its gridpoints, interpolated "
            "across the faces. "
            "Zone quantities (deformable blocks, 'gen edge'): sxx, syy, szz, sxy, sxz, syz (stress components), "
            "smin, smid, smax (principal stresses; smin is the most compressive), all in Pa with tension "
            "positive and one value per zone, each zone flat in its colour, over the range of the values drawn "
            "(with 'cut', of the section; 'map coolwarm' centres the range on 0, 'scale lo hi' fixes it); state (elastic, shear now, tension "
            "now, shear and tension now, yielded in the past); disp (displacement magnitude of the gridpoints, "
            "m, interpolated). 'zone' draws the surface of the zones (those whose centroid the range contains, "
            "when a range is given), or with 'cut' what lies below the plane and the section through each zone "
            "it crosses, with the block edges drawn over them; the deformable blocks are then left to it by "
            "'block'. "
            "Contact quantities: nstress (normal stress, compression positive), sstress (shear stress), ndis "
            "(normal closure, closing positive as in print and hist), sdis (shear displacement), state (elastic, slipping, open, "
            "failed), pp (pore pressure, Pa, with 'config flow') and aperture (hydraulic aperture, m). 'principal' in a model with zones draws at zone centroids three bars along the principal "
            "directions, as long as the stresses are large, black in compression and magenta in tension (colours "
            "no map uses, so they read over contours); many zones "
            "are thinned to about a thousand spread evenly, and with 'cut' the zones the plane crosses are "
            "taken, their bars on the plane. Without zones it draws, on each sub-contact, the normal stress "
            "along the normal and the shear stress along its direction as bars coloured by the signed value "
            "(compression negative). 'vector' draws arrows at the centroids of rigid blocks and at the surface "
            "gridpoints of deformable ones (on the section with 'cut'), thinned the same way. "
            "'magnify m' draws every point at its original place plus m times its displacement: gridpoints so, "
            "and rigid blocks moved by m times their displacement (not turned); 'magnify 0' shows the shape "
            "before the displacements (since the last 'reset disp'), and the title says the factor. Contacts are "
            "drawn where they are; on a section ('cut') a contact patch the plane crosses is drawn as its trace "
            "on the plane too, a band in its colour along the line where the joint meets the section. "
            "'cut plane dip d dd a [origin x,y,z]' cuts the model by a plane given as in 'jset' and removes what "
            "lies above it (on the side of its upward normal); unless a view is given, the eye looks straight "
            "at the cut face from that side, so 'cut plane dip 90 dd 180' removes the south half and shows the "
            "section from the south, and 'cut plane dip 0 dd 0 origin 0,0,2' shows a plan at z = 2 from above. "
            "Without 'file' the picture goes to the next free plot-0001.png, plot-0002.png, ... in the working "
            "directory, and the path is printed; with 'set echo on' the time the picture took is printed too. "
            "'plot set size w h view ... background ... map ...' keeps those options for later plots (until "
            "changed; 'new' keeps them) and draws nothing; 'plot set' alone prints them.");
        c.example("plot block disp");
        c.example("plot block zdis vector vel file 'slide.png' size 800 600 view -y");
        c.example("plot contact sstress range z 0 5");
        c.example("plot block group cut plane dip 90 dd 180 origin 0,2,0");
        c.example("plot block fixed ids");
        c.example("plot zone szz cut plane dip 90 dd 180");
        c.example("plot zone state principal cut plane dip 90 dd 90 origin 0.5,0,0");
        c.example("plot block disp magnify 200 vector disp");
        c.example("plot hist 2 vs 1 file 'fall.png'");
        c.example("plot cable");
        c.example("plot set size 1280 960 view eye 20,-30,15 background black map viridis");
        c.handle(handle_plot);
        return c;
    }();
    return spec;
}

} // namespace odec
