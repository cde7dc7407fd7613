// Every command of odec: each declared and handled in a file of its own, named after it,
// and listed once in registry.cpp.
#pragma once

#include "lang/parser.h"

namespace odec {

// The table of all commands, in the order `help` lists them.
const CommandTable& command_table();

// One function per command file.
const CommandSpec& cable_command();
const CommandSpec& liner_command();
const CommandSpec& call_command();
const CommandSpec& change_command();
const CommandSpec& damp_command();
const CommandSpec& fix_command();
const CommandSpec& fluid_command();
const CommandSpec& generate_command();
const CommandSpec& insitu_command();
const CommandSpec& free_command();
const CommandSpec& grav_command();
const CommandSpec& help_command_spec();
const CommandSpec& hist_command();
const CommandSpec& ini_command();
const CommandSpec& new_command();
const CommandSpec& poly_command();
const CommandSpec& print_command();
const CommandSpec& prop_command();
const CommandSpec& quit_command();
const CommandSpec& return_command();
const CommandSpec& set_command();
const CommandSpec& step_command();
const CommandSpec& title_command();
const CommandSpec& jset_command();
const CommandSpec& tunnel_command();
const CommandSpec& delete_command();
const CommandSpec& excavate_command();
const CommandSpec& fill_command();
const CommandSpec& group_command();
const CommandSpec& hide_command();
const CommandSpec& seek_command();
const CommandSpec& join_command();
const CommandSpec& table_command();
const CommandSpec& bound_command();
const CommandSpec& solve_command();
const CommandSpec& reset_command();
const CommandSpec& range_command();
const CommandSpec& save_command();
const CommandSpec& restore_command();
const CommandSpec& plot_command();
const CommandSpec& export_command();
const CommandSpec& config_command();
const CommandSpec& mscale_command();
const CommandSpec& show_command();
const CommandSpec& list_command();

} // namespace odec
