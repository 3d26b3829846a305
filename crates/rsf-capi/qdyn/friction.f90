! rsf's friction for QDYN. This file is rsf's own code (MIT, like the rest of the repository):
! it replaces QDYN's src/friction.f90 in a copy of a QDYN checkout (crates/rsf-capi/qdyn/run.sh
! does that; docs/faultsim.md describes the patch), keeping the module's name and its public
! interface, so QDYN's other sources compile against it unchanged. Every rate-and-state
! evaluation QDYN asks for goes through rsf's C ABI (include/rsf.f90, linked librsf_capi.a),
! one batch call over the mesh:
!
!   QDYN's i_rns_law   rsf's form                  parameters
!   0 classic          RSF_FORM_CLASSIC            f0 = mu_star, V0 = v_star
!   1 cut-offs         RSF_FORM_CUTOFF             f0 = mu_star, v0 = V1, each state's vc = V2
!   2 regularized      RSF_FORM_REGULARIZED        f0 = mu_star, V0 = v_star (SEAS 2018)
!   3 CNS              not rate-and-state: QDYN's own friction_cns module serves it
!
!   QDYN's itheta_law  rsf's law
!   1 aging            RSF_LAW_AGING
!   2 slip             RSF_LAW_SLIP
!   0 aging without    none: rsf does not provide this law (dθ/dt = −Vθ/Dc, no healing);
!     healing          a run that asks for it stops with that message
!
! rsf works in logs (ln V, ln θ): mu = f, dmu/dV = (∂f/∂ln V)/V, dmu/dθ = (∂f/∂ln θ)/θ and
! dθ/dt = θ d(ln θ)/dt. QDYN integrates V itself, and a trial stage of its solvers can reach
! V ≤ 0, where rate-and-state friction is not defined (QDYN's own formulas go on there: the
! log gives NaN for μ while the partials stay finite, for the aging law; the slip law's give
! NaN too). Under QDYN's Runge-Kutta-Fehlberg solvers (SOLVER = 2 and 3), such an element
! gets NaN for every output, the IEEE answer outside the domain, and the solver shortens the
! step (both check their stages or error for NaN). QDYN's Bulirsch-Stoer solver (SOLVER = 1)
! has no such check and would carry the NaN on, so there the run stops, naming the element
! and V. Any other refusal by rsf (parameters
! out of range) stops the run with rsf's message naming the element.
!
! Two things are kept between calls, neither changing a number: the elements' parameter
! structs, rebuilt only when a law or a parameter array differs from the last call's (QDYN's
! unit tests change them between calls); and the last evaluation, reused when V and θ are
! also bit-for-bit the same (QDYN asks for the state rate and then for the partials at the
! same (V, θ) in every right-hand side; one rsf call gives both).
module friction

  use iso_c_binding
  use, intrinsic :: ieee_arithmetic, only : ieee_value, ieee_quiet_nan
  use rsf
  use constants, only : SOLVER_TYPE
  use problem_class, only : problem_type

  implicit none
  private

  public :: set_theta_star, friction_mu, dmu_dv_dtheta, dtheta_dt

  ! the parameters the structs were built from, and the structs
  integer, save :: last_rns_law = -1, last_theta_law = -1
  double precision, dimension(:), allocatable, save :: last_a, last_b, last_dc, last_mu_star, &
    last_v_star, last_v1, last_v2
  type(RsfFrictionParams), dimension(:), allocatable, save :: fp
  type(RsfStateParams), dimension(:), allocatable, save :: sp
  ! the last evaluation: its V and θ (valid while the structs are unchanged) and its outputs
  logical, save :: have_last = .false.
  double precision, dimension(:), allocatable, save :: last_v, last_theta, last_mu, last_dmu_dv, &
    last_dmu_dtheta, last_dth_dt

contains

!--------------------------------------------------------------------------------------
! Whether the laws and parameters are those the structs were built from, bit for bit.
logical function same_parameters(pb)

  type(problem_type), intent(in) :: pb

  same_parameters = .false.
  if (.not. allocated(fp)) return
  if (size(fp) /= pb%mesh%nn) return
  if (last_rns_law /= pb%i_rns_law .or. last_theta_law /= pb%itheta_law) return
  same_parameters = all(last_a == pb%a) .and. all(last_b == pb%b) .and. all(last_dc == pb%dc) &
    .and. all(last_mu_star == pb%mu_star) .and. all(last_v_star == pb%v_star) &
    .and. all(last_v1 == pb%v1) .and. all(last_v2 == pb%v2)

end function same_parameters

!--------------------------------------------------------------------------------------
! The elements' parameter structs from QDYN's laws and parameter arrays (table above).
subroutine build_structs(pb)

  type(problem_type), intent(in) :: pb
  integer(c_int32_t) :: form, law
  integer :: i, n

  n = pb%mesh%nn
  select case (pb%i_rns_law)
  case (0)
    form = RSF_FORM_CLASSIC
  case (1)
    form = RSF_FORM_CUTOFF
  case (2)
    form = RSF_FORM_REGULARIZED
  case (3)
    stop 'friction (rsf): the CNS model (i_rns_law = 3) is not rate-and-state friction; QDYN serves it'
  case default
    stop 'friction (rsf): unknown friction law type'
  end select
  select case (pb%itheta_law)
  case (1)
    law = RSF_LAW_AGING
  case (2)
    law = RSF_LAW_SLIP
  case (0)
    stop 'friction (rsf): rsf does not provide the aging law without healing (itheta_law = 0)'
  case default
    stop 'friction (rsf): unknown state evolution law type'
  end select
  if (allocated(fp)) deallocate(fp, sp)
  allocate(fp(n), sp(n))
  do i = 1, n
    if (form == RSF_FORM_CUTOFF) then
      fp(i) = RsfFrictionParams(RSF_ABI_VERSION, form, pb%mu_star(i), pb%a(i), pb%v1(i))
      sp(i) = RsfStateParams(RSF_ABI_VERSION, law, pb%b(i), pb%dc(i), pb%v2(i))
    else
      fp(i) = RsfFrictionParams(RSF_ABI_VERSION, form, pb%mu_star(i), pb%a(i), pb%v_star(i))
      sp(i) = RsfStateParams(RSF_ABI_VERSION, law, pb%b(i), pb%dc(i), 0d0)
    end if
  end do
  last_rns_law = pb%i_rns_law
  last_theta_law = pb%itheta_law
  last_a = pb%a
  last_b = pb%b
  last_dc = pb%dc
  last_mu_star = pb%mu_star
  last_v_star = pb%v_star
  last_v1 = pb%v1
  last_v2 = pb%v2
  have_last = .false.

end subroutine build_structs

!--------------------------------------------------------------------------------------
! QDYN's normalisation of θ, kept for QDYN's other modules (rsf does not use it): Dc/V* for
! the classic and regularized laws, Dc/V2 with cut-offs, 1 for CNS.
subroutine set_theta_star(pb)

  type(problem_type), intent(inout) :: pb

  select case (pb%i_rns_law)
  case (0, 2)
    pb%theta_star = pb%dc / pb%v_star
  case (1)
    pb%theta_star = pb%dc / pb%v2
  case (3)
    pb%theta_star = 1
  case default
    stop 'set_theta_star (rsf): unknown friction law type'
  end select

end subroutine set_theta_star

!--------------------------------------------------------------------------------------
! Friction, its partials and the state rate at every node, from one rsf_batch_partials call.
subroutine rsf_evaluate(pb, v, theta, mu, dmu_dv, dmu_dtheta, dth_dt)

  type(problem_type), intent(in) :: pb
  double precision, dimension(pb%mesh%nn), intent(in) :: v, theta
  double precision, dimension(pb%mesh%nn), intent(out) :: mu, dmu_dv, dmu_dtheta, dth_dt
  double precision, dimension(pb%mesh%nn) :: ln_v, ln_theta, df_dln_v, df_dln_theta, rate
  logical, dimension(pb%mesh%nn) :: inside
  double precision :: nan
  integer(c_int) :: st
  integer :: i, n

  n = pb%mesh%nn
  if (.not. same_parameters(pb)) call build_structs(pb)
  if (have_last) then
    if (all(last_v == v) .and. all(last_theta == theta)) then
      mu = last_mu
      dmu_dv = last_dmu_dv
      dmu_dtheta = last_dmu_dtheta
      dth_dt = last_dth_dt
      return
    end if
  end if

  ! elements outside the domain (V or θ not positive and finite) are evaluated at V = θ = 1
  ! and their outputs replaced by NaN below
  inside = v > 0d0 .and. v <= huge(v) .and. theta > 0d0 .and. theta <= huge(theta)
  if (all(inside)) then
    ln_v = log(v)
    ln_theta = log(theta)
  else
    where (inside)
      ln_v = log(v)
      ln_theta = log(theta)
    elsewhere
      ln_v = 0d0
      ln_theta = 0d0
    end where
  end if
  st = rsf_batch_partials(int(n, c_size_t), fp, sp, ln_v, ln_theta, mu, df_dln_v, df_dln_theta, rate)
  if (st /= RSF_OK) then
    write (0, '(a,i0,a,a)') ' friction (rsf): rsf_batch_partials returned ', st, ': ', rsf_error_message()
    stop 'friction (rsf): rsf refused the evaluation'
  end if
  dmu_dv = df_dln_v / v
  dmu_dtheta = df_dln_theta / theta
  dth_dt = theta * rate
  if (.not. all(inside)) then
    if (SOLVER_TYPE /= 2 .and. SOLVER_TYPE /= 3) then
      i = findloc(inside, .false., dim=1)
      write (0, '(a,i0,a,es12.4,a,es12.4,a)') ' friction (rsf): the solver asked for friction at element ', i, &
        ', V = ', v(i), ' m/s, theta = ', theta(i), ' s: rate-and-state friction is defined for V > 0 and theta > 0'
      stop 'friction (rsf): outside V > 0, and this solver does not reject a NaN step (SOLVER = 2 or 3 does)'
    end if
    nan = ieee_value(nan, ieee_quiet_nan)
    where (.not. inside)
      mu = nan
      dmu_dv = nan
      dmu_dtheta = nan
      dth_dt = nan
    end where
  end if

  last_v = v
  last_theta = theta
  last_mu = mu
  last_dmu_dv = dmu_dv
  last_dmu_dtheta = dmu_dtheta
  last_dth_dt = dth_dt
  have_last = .true.

end subroutine rsf_evaluate

!--------------------------------------------------------------------------------------
function friction_mu(v, theta, pb) result(mu)

  type(problem_type), intent(in) :: pb
  double precision, dimension(pb%mesh%nn), intent(in) :: v, theta
  double precision, dimension(pb%mesh%nn) :: mu, dmu_dv, dmu_dtheta, dth_dt

  if (pb%i_rns_law == 3) then
    write (6, *) "friction.f90::friction_mu is deprecated for the CNS model"
    stop
  end if
  call rsf_evaluate(pb, v, theta, mu, dmu_dv, dmu_dtheta, dth_dt)

end function friction_mu

!--------------------------------------------------------------------------------------
subroutine dtheta_dt(v, tau, sigma, theta, theta2, dth_dt, dth2_dt, pb)

  use friction_cns, only : dphi_dt

  type(problem_type), intent(in) :: pb
  double precision, dimension(pb%mesh%nn), intent(in) :: v, tau, sigma
  double precision, dimension(pb%mesh%nn), intent(in) :: theta, theta2
  double precision, dimension(pb%mesh%nn) :: dth_dt, dth2_dt
  double precision, dimension(pb%mesh%nn) :: mu, dmu_dv, dmu_dtheta

  if (pb%i_rns_law == 3) then
    ! CNS: porosity and its rate come from QDYN's own CNS module
    call dphi_dt(v, tau, sigma, theta, theta2, dth_dt, dth2_dt, pb)
  else
    call rsf_evaluate(pb, v, theta, mu, dmu_dv, dmu_dtheta, dth_dt)
  end if

end subroutine dtheta_dt

!--------------------------------------------------------------------------------------
subroutine dmu_dv_dtheta(dmu_dv, dmu_dtheta, v, theta, pb)

  type(problem_type), intent(in) :: pb
  double precision, dimension(pb%mesh%nn), intent(in) :: v, theta
  double precision, dimension(pb%mesh%nn), intent(out) :: dmu_dv, dmu_dtheta
  double precision, dimension(pb%mesh%nn) :: mu, dth_dt

  if (pb%i_rns_law == 3) then
    write (6, *) "friction.f90::dmu_dv_dtheta is deprecated for the CNS model"
    stop
  end if
  call rsf_evaluate(pb, v, theta, mu, dmu_dv, dmu_dtheta, dth_dt)

end subroutine dmu_dv_dtheta

end module friction
