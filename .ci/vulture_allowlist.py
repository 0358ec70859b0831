"""Names vulture (dead-code search, `.ci/run`) cannot see used: they are called by a framework, by name, or by a
protocol.  One line per name, with who uses it; anything else vulture reports is dead code to remove."""

# Python protocols and callbacks with a fixed signature
__getattr__  # the lazy public names of designer/__init__.py (module __getattr__)
__dir__  # the same
_.showwarning  # warnings.showwarning replaced by the CLI (designer/cli/__init__.py)
file  # its signature's argument
signum  # signal handler arguments (designer/errors.py)
frame
_.terminal  # scipy solve_ivp event attributes (terminal, direction)
study_  # optuna's trial callback argument (designer/studies/explore/_workers.py)
_._rng  # optuna sampler attribute set for reseed_rng (designer/studies/explore/_operators.py)
_._split_lines  # argparse.HelpFormatter's hooks, overridden (designer/cli/_parser.py)
_.whitespace_split  # shlex.shlex settings (tests/cli/test_one_screen.py)
_.commenters
checkout  # a pytest fixture taken by name (usefixtures: tests/cli/test_one_screen.py)

# called by name
figure_trail  # report/figures.py: getattr(figures, f"figure_{name}") for each of plots.figures.FIGURES
figure_inertia
figure_threshold
figure_groove_damper
_._draw_line  # plots/svg.py: getattr(self, "_draw_" + kind) for each recorded artist
_._draw_markers
_._draw_hline
_._draw_vline
_._draw_vspan
_._draw_rect
_._draw_bars
_._draw_bands
_._draw_contour
_._draw_clabel
_._draw_annotate
first_row_marked  # read by the Jinja templates (report/templates/_panels.*.j2)
write_docs  # the documented command that regenerates docs/parameters.md (CONTRIBUTING)
stem_figure  # docs/img/render.py draws docs/retrofit-stem.png with it (the documented regeneration)
_.residuals  # public property of a calibration result (notebooks)

# web framework: Dash callbacks, Flask hooks and overrides (designer/studio)
open_card
fill_limits  # the card's acceptance limits, after the chart (designer/studio/app.py)
_.validation_layout  # Dash: the ids a callback may target outside the first layout
check_mine
save
_local_only
_headers  # Flask after_request: the security headers of every answer (designer/studio/server.py)
_.index_string  # Dash: the page with the studio's style sheet
_.log_request

# pytest and test helpers: hooks and fixtures used by name, HTMLParser and Selenium overrides
pytest_configure
pytest_collection_modifyitems  # tests/conftest.py: the slowest modules first under pytest-xdist
_alone_under_xdist
fast_simulation_report
no_solvers
Bad  # a record class whose definition must raise (tests/test_records.py)
_quiet_extrapolation
_close_figures
_.handle_starttag
_.handle_startendtag
_.handle_endtag
_.handle_data
pytestmark
_.binary_location
dask_setup  # Dask's preload hook (designer/children.py: preload=["designer.children"] in studies/fleet)
worker  # its argument
_.turning_moment  # a Casters column read by key (designer evaluate's table)

# record fields and methods read by name through a record's declared keys (designer.reprs.Key: "*" gives every
# repr field to to_dict; a Key's source may name an attribute or a method, "part.doubled()")
failed_amplitudes  # BifurcationDiagram (designer/studies/dynamics/limit_cycles/_results.py): bifurcation.json
rolling_sim_bracket  # Table1Row: bifurcation.json's table1 rows
tyre_sim_bracket
tyre_onset_below_scan  # MapCell: stiffness_mass_map.csv
stable_max_multiplier
knock_safe_rtol  # LimitCycleStudy: bifurcation.json
knock_safe_error
today_bracket  # the rolling-limit record: bifurcation.json
tyre_limit_bracket
hypervolume_explored  # FrontComparison (designer/studies/explore/_result.py): explore.json's comparison
hypervolume_exact
hypervolume_explored_normalised
hypervolume_exact_normalised
reference_normalised
_.single_part_fix_exists  # FixResult's key in designer fix --json (designer/studies/retrofit/_records.py)
doubled  # tests/test_records.py: a method a Key reads by its path ("part.doubled()")
_.renderer  # dash.Dash's renderer script (designer/studio/app.py: RENDERER numbers the page's requests)
