// The one list of commands: to add a command, write its file and add one line here.
#include "commands.h"

namespace odec {

const CommandTable& command_table() {
    static const CommandTable table = [] {
        CommandTable t;
        t.commands = {
            &new_command(),    &title_command(), &call_command(),  &return_command(), &quit_command(),
            &help_command_spec(), &poly_command(), &prop_command(), &change_command(), &grav_command(),
            &fix_command(),    &free_command(),  &ini_command(),   &damp_command(),   &set_command(),
            &step_command(),   &hist_command(),  &print_command(),
            &plot_command(),   &export_command(), &save_command(),  &restore_command(),
        };
        return t;
    }();
    return table;
}

} // namespace odec
