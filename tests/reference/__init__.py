"""Independent reference solutions for the physics validations (``test_validate_*``).

Each reference solves one physical problem from first principles -- a closed form,
a quadrature of an energy integral, or Newton's laws integrated by scipy -- and is the
answer a validation compares the package against. None imports ``dominowave.theory``
(the closed forms under test); a reference may read a dominowave object's inputs
(``planar_chain.chain_collisions`` reads a chain's geometry), never its results.
tests/reference/test_reference.py checks each reference against a closed form, a limit,
a conservation law or a second method. Import as ``from reference.rigid_chain import
ej_fall_time`` (pytest puts tests/ on sys.path through tests/conftest.py).

Catalogue: problem -- method -- used by

rigid_chain (EJ's rigid dominoes, point mass at the tip, eqs 2-14)
  ej_fall_time: fall 0 -> beta with Omega (eq 11) -- quad after sinh substitution,
      epsrel 1e-13 -- theory/test_theory_rigid (fall time, eq 13), via ej_transient_arrivals
  fall_by_newton: fall theta0 -> beta, Newton's law -- solve_ivp DOP853 rtol 1e-13,
      atol 1e-15, event -- via ej_chain_by_newton, compliant_collision.thick_chain_speed
  ej_collision: collision eq 2 (energy + angular momentum) -- brentq rtol 1e-15 --
      theory/test_theory_rigid (eq 8, eq 9 fixed point)
  ej_chain_by_newton: start times of a rigid chain -- fall_by_newton + ej_collision --
      theory/test_theory_rigid (arrival times)
  ej_transient_arrivals: arrival times and limit speed (eqs 4-9, 14) -- recursion eq 6
      + ej_fall_time -- chain/test_chain_wave (steady-speed fit)
  hinged_fall_time_from_rest: any hinged body from rest at theta0 -- quad after
      theta = theta0 + x^2, epsrel 1e-12 -- rods/test_rods_validate (fall, base reaction)
compliant_collision (two hinged dominoes and a linear spring, eqs 15-31)
  linear_contact: duration and outgoing velocities, any lever arms -- closed form
      (half sine) -- rods/test_rods_validate (two-body collision)
  head_on_contact: the paper's Fig 3 contact, frozen geometry -- solve_ivp DOP853
      rtol 1e-12, atol 1e-16, event -- theory/test_theory_compliant (T_c, eqs 17, 29-32, 37)
  thick_chain_speed: wave speed of thick compliant dominoes -- fall_by_newton +
      head_on_contact per domino -- theory/test_theory_compliant (eq 34)
contact_mechanics (one normal contact)
  hertz_collision: Hertz impact duration and overlap -- closed form (Euler's beta
      function), Johnson 1985 -- rods/test_rods_validate (Hertz law)
  dashpot_restitution: restitution of the clipped spring-dashpot -- closed form,
      Schwager & Poeschel 2007 eq 20 -- rods/test_rods_validate (dashpot)
rolling_column (the DEM domino: spheres rolling without slip on their base sphere)
  rolling_column_time: tilt theta0 -> theta_end -- quad of the energy integral,
      epsrel 1e-12 -- chain/test_chain_build (clump mapping), chain/test_chain_dem (first
      collision), dem/test_dem_rigid (pivot fall)
  rolling_column_friction_ratio: friction needed to roll -- energy + Lagrange equation
      on a grid -- dem/test_dem_rigid (pivot fall)
  rolling_column_contact_angle: tilt of first touch with the next column -- brentq
      xtol 1e-15 -- chain/test_chain_dem (first collision)
  rolling_column_by_ode: the same fall, Lagrange equation -- solve_ivp RK45 rtol 1e-12,
      atol 1e-14 -- test_reference (checks rolling_column_time)
rigid_body (free rigid bodies)
  free_rotation: Euler's torque-free equations -- solve_ivp RK45 rtol 1e-11, atol 1e-13
      -- dem/test_dem_rigid (tennis racket)
  quaternion_matrix: rotation of a unit quaternion -- closed form -- dem/test_dem_rigid
planar_chain (planar rigid dominoes of spheres, linear springs, no friction)
  PlanarBodies, planar_chain_collisions, chain_collisions: contact onset times --
      solve_ivp DOP853 rtol 1e-11, atol 1e-14, events -- chain/test_chain_dem (collisions),
      benchmarks/yade/converge_yade.py
block_statics (a block pushed on its back face, section 2.4, eqs 38-42)
  moment, block_moment_about_com, sign_change_force: regime boundaries as sign changes
      of signed moments -- cross products + brentq xtol 1e-14 -- theory/test_theory_bounds
cuboid (uniform and rounded cuboids: mass properties)
  box_mass_properties, box_edge_inertia, parallel_axis: mass, principal moments, moment
      about an edge -- closed form (Steiner) -- dem/test_dem_box_validate (the box's mass)
  rounded_box_mass_properties, rounded_rectangle_mass_properties: box or rectangle swept
      by a sphere (disc), exact -- closed form piece by piece (core, slabs, quarter
      cylinders, octants), checked by 2D quadrature to 4e-16 -- test_cuboid_references
incline (a block on an incline with Coulomb friction)
  incline_regime, incline_acceleration, incline_motion, incline_corner_forces: rest,
      slide a = g (sin t - mu cos t), tip at tan t > s / 2h; stopping; two-point statics
      -- closed form -- test_cuboid_references
edge_tipping (a cuboid tipping over its bottom front edge, hinge fixed)
  edge_fall_time: theta0 -> theta1 from (theta0, omega0) -- quad of the energy integral
      after theta = theta0 + x^2, epsrel 1e-13 -- dem/test_dem_box_validate (the r = 0
      end of the sharp-edge trend)
  edge_fall_by_newton: the same, Newton's law -- solve_ivp DOP853 rtol 1e-12, atol
      1e-14, event -- test_cuboid_references (checks edge_fall_time)
  edge_reaction, edge_slip_tilt: floor force on the edge per unit mass; the first tilt
      needing more friction than mu -- closed form, scan + brentq xtol 1e-14 (from rest
      every box slips near theta = alpha + acos(1/3), before it lands)
  first_contact_time: Push(omega) of domino 0 to its first touch of domino 1 at
      sin(theta) = d / l (top front edge on the back face) -- edge_fall_time --
      test_cuboid_references
rigid_impact (two rigid bodies colliding at a point, no friction)
  effective_mass, impulse_collision, energy_loss: 1/m_eff with both lever arms and
      inertias, Newton's restitution law, loss (1 - e^2) m_eff u^2 / 2 -- closed form --
      test_cuboid_references
  dashpot_for_restitution, compliant_impact: the same impact through a spring-dashpot at
      frozen geometry -- solve_ivp DOP853 rtol 1e-12, event -- checks the two above
resting_box (a box resting flat on n corner springs)
  resting_corner_load, resting_box_modes: m g / n per corner, overlap m g / (n k);
      bounce, rocking (with sliding for k_t > 0, gravity's -m g h), yaw -- closed form,
      checked against the exact potential's Hessian -- dem/test_dem_box_validate (at rest)
  stack_loads, stack_bounce_frequencies: a stack of N boxes, loads (N - i) m g / n and
      the fixed-free chain's vertical modes -- closed form, checked against the spring
      chain's static solution and eigenvalues -- dem/test_dem_box_validate (a stack at
      rest)
rounded_tipping (a rounded cuboid rolling over its rounded front bottom edge, no slip)
  rounded_fall_time: theta0 -> theta1 -- quad of the energy integral with the rolling
      inertia j(theta), epsrel 1e-13 -- dem/test_dem_box_validate (sharp-edge limit,
      r = s/20 and s/200)
  rounded_fall_by_lagrange: the same, Lagrange's equation -- solve_ivp DOP853 rtol
      1e-12, atol 1e-14, event
  rounded_first_contact_time: (l - 2r) sin(theta) + r theta = d -- brentq xtol 1e-15 and
      rounded_fall_time; checked against a polygon-distance event --
      dem/test_dem_box_validate (two-box first touch), chain/test_chain_box
box_distance (distances of cuboid cores: the overlap of rounded cuboids)
  box_box_distance: closest points of two boxes -- bounded least squares (lsq_linear,
      BVLS), checked by closed forms and a separating-plane certificate --
      test_cuboid_references
  box_point_distance, box_wall_distance: box-sphere and box-wall -- closed form (clamp,
      lowest corner) -- test_cuboid_references
sliding_contact (a rounded box driven at constant velocity over a fixed one, full slip)
  sliding_contact: force k_n delta n - mu k_n delta t and stored energy along the path --
      box_box_distance (exact core distance, any feature pair) + closed form; checked
      against a vertex over a face and over an edge -- dem/test_dem_box_validate
      (feature changes)
leaning_frictionless (the leaning train without friction: geometry + conservation laws)
  train_tilts: the train's tilts -- brentq (xtol 1e-15) on the corner's distance from the
      next back face -- used by frictionless_steady_speed
  frictionless_steady_speed: steady speed -- generalised momentum in the collision, energy
      in the fall, Phi by central differences, Gauss-Legendre fall time (1e-10) --
      theory/test_theory_leaning (frictionless limit)
leaning_train (the leaning train with friction, one body per domino)
  simulate_train: hits, angular velocities, losses -- Lagrange multipliers solved with the
      accelerations, Baumgarte, solve_ivp DOP853 rtol 1e-10 with events, impulse problems
      over the whole train -- theory/test_theory_leaning (transient);
      test_leaning_reference checks it against the pendulum quadrature, an energy balance
      and hand-solved two-domino impacts
"""
