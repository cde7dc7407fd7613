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
        c.keyword("flow", 4, "fluid flow in the joints ('config flow' first): 'on' or 'off'; 'steady' (pressures "
                             "head for the steady field, each node at its own step) or 'transient' (they follow "
                             "the model's time); one of each pair may be given together, as UDEC writes them "
                             "('set flow steady off'); UDEC's 'clear' is refused")
            .one_of("what", {"on", "off", "steady", "transient", "clear"})
            .repeat();
        c.keyword("substeps", 4, "steady flow: flow sub-steps per mechanical step").integer("n", 1, 100000).defaults("1");
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
        c.keyword("energy", 3, "'on': keep the energy account from now on (kinetic and strain energy, the work of "
                               "gravity, loads and prescribed velocities, what damping, joint slip and zone "
                               "plasticity dissipate, and the error of the balance: 'print energy', 'hist energy "
                               "term', the FISH energy_* intrinsics); 'off': stop and drop it. Meant for dynamic "
                               "analysis ('config dyn'): with scaled masses the energies are not physical")
            .one_of("state", {"on", "off"});
        c.keyword("large", 2, "large-strain mode (the default): zones follow their gridpoints' positions");
        c.keyword("small", 2, "small-strain mode: zone geometry stays as it was zoned (rigid blocks still move "
                              "by large displacements)");
        c.describe("A word that is no setting names a FISH variable: 'set name = value ...' gives FISH "
                   "variables values (numbers, 'strings', vectors (x,y,z) or the values of other FISH names), "
                   "as classic scripts do before they call their functions. A new name needs the '='.\n\n"
                   "'set energy on' keeps an energy account from then on, in joules. Stored now: 'kinetic' (the "
                   "free blocks' translation and rotation and the free gridpoints' motion, with the real masses; "
                   "prescribed velocity components left out), 'jstrain' (the joints' springs: per sub-contact "
                   "area x (sn^2 / 2 kn + |ss|^2 / 2 ks), a joint in tension or a joined one pulled apart "
                   "included, an open one nothing) and 'zstrain' (the zones' elastic strain energy, volume x "
                   "(p^2 / 2 K + s:s / 4 G) for the stress each holds). Work done on the model since, positive "
                   "when it puts energy in: 'gravity' (the weights times the displacements), 'load' ('bound "
                   "xload ...' and 'bound stress' times the displacements), 'velocity' (what drives the "
                   "prescribed velocity components: the reaction, minus the other forces on them, times their "
                   "displacement), and 'boundary' = load + velocity. Dissipated since, positive when it takes "
                   "energy out: 'damping', 'slip' (in the joints: the mean shear stress of each step times its "
                   "plastic slip, less the work of dilation against the normal stress, and what a joint's "
                   "springs held when it breaks in tension or opens under a shear stress) and 'plastic' (the "
                   "zones' stress work less the change of their elastic energy, where they yield). 'initial' is "
                   "the stored energy when the account began, 'given' what commands changed it by between steps "
                   "('ini', 'insitu', 'delete', 'excavate', FISH). The balance is kinetic + jstrain + zstrain + "
                   "damping + slip + plastic = initial + given + gravity + boundary, and 'error' is the left side "
                   "less the right: what the cycle made or lost on its own. An explicit step is exact for free "
                   "flight and for a joint that stays closed; contacts that close or open within a step, and "
                   "sub-contacts made already pressed in (their closure taken whole) give or take energy, and "
                   "show in 'error'.\n\n"
                   "The account stands where the joints' and zones' stresses stand: at the start of the last "
                   "step (time t - dt), the work as the trapezoidal rule over each step's displacement, the "
                   "kinetic energy as m v- . v+ / 2 with the half-step velocities on either side (the form the "
                   "central differences conserve; it dips below zero, by m a^2 dt^2 / 8, where a block turns "
                   "back at rest). It is meant for dynamic analysis ('config dyn', real masses, 'damp off' or a "
                   "physical damping): in static mode, and where 'mscale' raised masses, blocks move with masses "
                   "not theirs, and the kinetic energy and the balance are not physical ('set energy on' and "
                   "'print energy' say so). While it is off nothing is computed; on, each step's increments are "
                   "summed in a fixed order, the same bits with any number of threads. Save files keep it; "
                   "'reset energy' starts it afresh, 'set energy off' drops it.");
        c.example("set dt 1e-4 echo off");
        c.example("set kn = 1e10 name = 'run1'");
        c.example("set energy on");
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
            for (const char* k : {"flow", "substeps"}) {
                if (a.has(k) && !m.flow.configured) {
                    fail(a.find(k)->loc, "fluid flow is not configured", {"give 'config flow' first (3DEC writes 'config fluid')"}, "set");
                }
            }
            if (const KeywordUse* f = a.find("flow")) {
                // 'set flow steady off' (UDEC): one word of each pair, checked before anything changes.
                const Value* state = nullptr;
                const Value* mode = nullptr;
                for (const Value& v : f->values) {
                    if (v.text == "clear") {
                        fail(v.loc, "'set flow clear' (UDEC) has no counterpart in odec",
                             {"odec's flow state is the flow nodes' pressures and fixities: set the pressures again "
                              "with 'insitu pp p' or 'insitu wtable z', release fixed ones with 'bound pfree'"},
                             "set");
                    }
                    const Value*& slot = (v.text == "on" || v.text == "off") ? state : mode;
                    if (slot) {
                        fail(v.loc, "'" + v.text + "' after '" + slot->text + "': 'set flow' takes one of 'on'/'off' and "
                                    "one of 'steady'/'transient'", {}, "set");
                    }
                    slot = &v;
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
            if (a.has("energy")) {
                if (a.text("energy") == "off") {
                    m.energy = EnergyAccount();
                } else if (m.energy.on) {
                    if (!ctx.interp.quiet) {
                        ctx.out << "note: the energy account is already on (since step " << m.energy.start_step
                                << "): it goes on; 'reset energy' starts it afresh\n";
                    }
                } else {
                    start_energy_account(m);
                    const std::string caveat = energy_caveat(m);
                    if (!caveat.empty()) warn(ctx, a.find("energy")->loc, caveat);
                }
            }
            if (a.has("echo")) ctx.interp.echo = a.text("echo") == "on";
            if (a.has("gravity")) m.gravity = a.vec("gravity");
            if (a.has("ncyc")) m.histories.ncyc = a.integer("ncyc");
            if (const KeywordUse* f = a.find("flow")) {
                for (const Value& v : f->values) {
                    const std::string& w = v.text;
                    if (w == "on" || w == "off") {
                        m.flow.on = w == "on";
                        m.geometry_changed = true; // held blocks have contacts only with flow on
                    }
                    else m.flow.mode = w == "steady" ? FlowMode::Steady : FlowMode::Transient;
                }
                m.flow.last_volume.clear();
            }
            if (a.has("substeps")) m.flow.substeps = a.integer("substeps");
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
