#include "commands.h"
#include "common.h"
#include "engine/parallel.h"

namespace odec {

const CommandSpec& set_command() {
    static const CommandSpec spec = [] {
        CommandSpec c("set", 3, "change a setting of the model or of the program");
        c.keyword("dt", 2, "force this timestep, s ('auto' or 0: back to the automatic one)").real("dt", 0).or_word("auto");
        c.keyword("dtfrac", 3, "fraction of the critical timestep used").real("f", 0, 1, Limit::Open).defaults("0.1");
        c.keyword("ctol", 2, "contact tolerance, m (0: chosen from block sizes)").real("tol", 0);
        c.keyword("ovtol", 2, "overlap tolerance, m: the deepest overlap allowed when cycling starts between blocks "
                              "that carry no stress yet; deeper ones stop the cycling command with an error that "
                              "names them (0: 0.5 % of the smaller block's size, the cube root of its volume)")
            .real("tol", 0);
        c.keyword("echo", 2, "echo script commands with their file and line").one_of("state", {"on", "off"}).defaults("on");
        c.keyword("log", 3, "copy the commands and what they print into the log file").one_of("state", {"on", "off"}).defaults("off");
        c.keyword("logfile", 4, "the log file (appended to)").string("name").defaults("odec.log");
        c.keyword("gravity", 3, "gravity vector, m/s^2 (same as 'grav')").vec("g");
        c.keyword("ncyc", 2, "steps between history samples").integer("n", 1).defaults("10");
        c.keyword("jmat", 4, "joint material of contacts made from now on").integer("n", 1, 1000000).defaults("1");
        c.keyword("jcons", 4, "joint model of contacts made from now on").integer("j", 1, 2).defaults("1");
        c.keyword("plot", 2, "picture options kept between plots: the options of 'plot set'").forward_to("plot");
        c.keyword("dynamic", 3, "'off': static analysis, masses scaled for convergence (and local damping if the "
                                "damping set does not solve statically); 'on': dynamic analysis, real masses and "
                                "real time (needs 'config dyn' first, as in 3DEC)").one_of("state", {"on", "off"});
        c.keyword("threads", 3, "threads the cycle runs on (results are the same bits with any number; the default is "
                                "the environment variable ODEC_THREADS, else every core)")
            .integer("n", 1, 1024);
        c.keyword("large", 2, "large-strain mode (the default): zones follow their gridpoints' positions");
        c.keyword("small", 2, "small-strain mode: zone geometry stays as it was zoned (rigid blocks still move "
                              "by large displacements)");
        c.describe("A word that is no setting names a FISH variable: 'set name = value ...' gives FISH "
                   "variables values (numbers, 'strings', vectors (x,y,z) or the values of other FISH names), "
                   "as classic scripts do before they call their functions. A new name needs the '='.");
        c.example("set dt 1e-4 echo off");
        c.example("set kn = 1e10 name = 'run1'");
        c.handle([](CommandContext& ctx, const Args& a) {
            Model& m = ctx.model;
            if (a.has("dynamic") && a.text("dynamic") == "on" && !m.settings.dyn_configured) {
                fail(a.find("dynamic")->values[0].loc, "dynamic analysis is not configured",
                     {"give 'config dyn' first (as in 3DEC): without it an analysis is static"}, "set");
            }
            if (a.has("dynamic") && a.text("dynamic") == "off") {
                Damping& d = ctx.model.damping;
                if (d.mode == DampingMode::Off || d.mode == DampingMode::Rayleigh) {
                    d.mode = DampingMode::Local;
                    d.local = 0.8;
                    if (!ctx.interp.quiet) ctx.out << "static solution: local damping 0.8\n";
                }
            }
            if (a.has("small") && a.has("large")) fail(a.find("small")->loc, "'small' and 'large' exclude each other", {}, "set");
            if (a.uses.empty()) fail(a.loc, "'set' needs a setting", {"type 'help set' for the settings"}, "set");
            if (a.has("jmat")) defined_joint_material(m, a, "set");
            if (a.has("logfile")) check_file_allowed(ctx, a.find("logfile")->values[0].loc, a.text("logfile"), "set");
            if (const KeywordUse* p = a.find("plot")) {
                // `set plot size 800 600 view -y` is `plot set size 800 600 view -y`.
                std::vector<Token> toks;
                Token verb;
                verb.kind = TokenKind::Word;
                verb.text = verb.lower = "plot";
                verb.loc = p->loc;
                toks.push_back(verb);
                Token set = verb;
                set.text = set.lower = "set";
                toks.push_back(set);
                toks.insert(toks.end(), p->rest.begin(), p->rest.end());
                const Args fwd = parse_command(ctx.interp.table, toks, &ctx.interp.named_ranges);
                fwd.command->handler(ctx, fwd);
            }
            const std::string old_log_path = ctx.interp.log_path;
            if (a.has("logfile")) {
                const bool was_on = ctx.interp.log_is_on();
                const std::string old = ctx.interp.log_path;
                ctx.interp.log_path = a.text("logfile");
                std::string error;
                if (was_on && !ctx.interp.open_log(error)) {
                    ctx.interp.log_path = old;
                    ctx.interp.open_log(error);
                    fail(a.find("logfile")->values[0].loc, error, {}, "set");
                }
            }
            if (a.has("log")) {
                if (a.text("log") == "on") {
                    std::string error;
                    if (!ctx.interp.open_log(error)) {
                        ctx.interp.log_path = old_log_path; // a failed command changes nothing
                        fail(a.find("log")->values[0].loc, error, {}, "set");
                    }
                } else {
                    ctx.interp.close_log();
                }
            }
            if (a.has("dt")) {
                m.settings.dt_fixed = a.text("dt") == "auto" ? 0.0 : a.real("dt");
                m.geometry_changed = true;
            }
            if (a.has("dtfrac")) {
                m.settings.dtfrac = a.real("dtfrac");
                m.geometry_changed = true;
            }
            if (a.has("ctol")) {
                m.settings.ctol = a.real("ctol");
                m.geometry_changed = true;
            }
            if (a.has("ovtol")) m.settings.ovtol = a.real("ovtol");
            if (a.has("dynamic")) {
                m.settings.dynamic = a.text("dynamic") == "on";
                m.geometry_changed = true; // the masses are chosen again
            }
            if (a.has("threads")) {
                set_thread_count(a.integer("threads"));
                if (!threads_available()) {
                    warn(ctx, a.find("threads")->loc, "this odec was built without OpenMP: the cycle runs on one thread");
                }
            }
            if (a.has("echo")) ctx.interp.echo = a.text("echo") == "on";
            if (a.has("gravity")) m.gravity = a.vec("gravity");
            if (a.has("ncyc")) m.histories.ncyc = a.integer("ncyc");
            if (a.has("jmat")) m.settings.default_jmat = a.integer("jmat");
            if (a.has("jcons")) m.settings.default_jcons = a.integer("jcons");
            if (a.has("small") || a.has("large")) {
                m.settings.large_strain = a.has("large");
                m.geometry_changed = true;
            }
        });
        return c;
    }();
    return spec;
}

} // namespace odec
