// `export vtk 'name'`: the model as VTK XML files for ParaView (io/vtk_export.h), with the
// contacts and sub-contacts as the contact bridge sees them, so ParaView shows what
// `plot contact` shows.
#include "commands.h"
#include "engine/flow.h"
#include "common.h"

#include "io/vtk_export.h"
#include "render/contact_bridge.h"

namespace odec {

const CommandSpec& export_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("export", 3, "write the model as files for other programs");
        c.keyword("vtk", 2, "VTK XML files for ParaView: blocks and zones (.vtu), contacts, sub-contacts and cables (.vtp), and a .pvd")
            .string("name")
            .in_choice(1);
        c.require_one_of(1);
        c.describe("'export vtk name' writes name-blocks-<step>.vtu (blocks with cell data 'displacement' "
                   "of the centroid (m), 'velocity' (m/s), 'rotation' (the turn since 'reset disp' as a rotation "
                   "vector: axis times angle, rad, right-hand rule about the world axes), material, group and "
                   "region, and point data 'displacement' and 'velocity' of each vertex, exact for any "
                   "rotation), name-contacts-<step>.vtp and name-subcontacts-<step>.vtp "
                   "(contact points with normal, area, normal and shear stress, normal and shear displacement, "
                   "force and state; with 'config flow' also 'pore_pressure', Pa, and 'aperture', the hydraulic "
                   "aperture, m) and name.pvd, the collection ParaView opens. When blocks are deformable, "
                   "name-zones-<step>.vtu holds their zones as tetrahedra at the current gridpoint positions, "
                   "with cell data 'stress' (Pa, tension positive; a symmetric tensor of 6 components in VTK's "
                   "order xx, yy, zz, xy, yz, xz), 'smin', 'smid', 'smax' (principal stresses, Pa, smin the most "
                   "compressive), 'state' (bits: 1 shear now, 2 tension now, 4 shear past, 8 tension past), "
                   "'model' (0 null, 1 elastic, 2 Mohr-Coulomb), 'block_id' and 'zone' (its number), and point "
                   "data 'gridpoint' (its number), 'displacement' (m) and 'velocity' (m/s). Exporting again at "
                   "a later step adds that step to the same name.pvd, so ParaView plays the steps in order. The "
                   "name may carry a directory; an extension (.vtu, .vtp, .pvd, .vtk) is dropped.");
        c.example("export vtk 'slope'");
        c.handle([](CommandContext& ctx, const Args& a) {
            const Value& name = a.find("vtk")->values[0];
            check_file_allowed(ctx, name.loc, name.text, "export");
            if (ctx.model.flow.configured && ctx.model.contacts.detected) {
                // The pore pressures and apertures of the contacts as they stand.
                flow_sync(ctx.model);
                flow_apertures(ctx.model);
            }
            const Model& m = ctx.model;
            const ContactView contacts = make_contact_view(m);
            std::vector<std::string> written;
            std::string error;
            if (!export_vtk(m, &contacts, name.text, written, error)) fail(name.loc, error, {}, "export");
            if (ctx.interp.quiet) return;
            ctx.out << "export: wrote";
            for (size_t k = 0; k < written.size(); ++k) ctx.out << (k ? ", " : " ") << written[k];
            ctx.out << "\n";
        });
        return c;
    }();
    return spec;
}

} // namespace odec
