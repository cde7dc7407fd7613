// The one list of commands: to add a command, write its file and add one line here.
#include "commands.h"

namespace odec {

const CommandTable& command_table() {
    static const CommandTable table = [] {
        CommandTable t;
        t.commands = {
            // the session
            &new_command(), &title_command(), &call_command(), &return_command(), &quit_command(),
            &help_command_spec(), &config_command(),
            // geometry
            &poly_command(), &jset_command(), &tunnel_command(), &delete_command(), &excavate_command(), &fill_command(),
            &group_command(), &hide_command(), &show_command(), &seek_command(), &join_command(), &range_command(),
            &generate_command(),
            // properties and conditions
            &prop_command(), &change_command(), &grav_command(), &fix_command(), &free_command(), &cable_command(), &fluid_command(), &liner_command(),
            &bound_command(), &insitu_command(), &ini_command(), &table_command(), &damp_command(), &mscale_command(), &set_command(),
            // solution
            &step_command(), &solve_command(), &reset_command(),
            // results
            &hist_command(), &print_command(), &list_command(), &plot_command(), &export_command(), &save_command(),
            &restore_command(),
        };
        return t;
    }();
    return table;
}

} // namespace odec
