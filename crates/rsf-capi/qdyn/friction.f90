! rsf's friction for QDYN. This file is rsf's own code (MIT, like the rest of the repository):
! it replaces QDYN's src/friction.f90 in a copy of a QDYN checkout (crates/rsf-capi/qdyn/run.sh
! does that; docs/faultsim.md describes the patch), keeping the module's name and its public
! interface, so QDYN's other sources compile against it unchanged. Every rate-and-state
! evaluation QDYN asks for goes through rsf's C ABI (include/rsf.f90, linked librsf_capi):
! a mesh (rsf_mesh_new) holds every node's parameters, checked once, and each call is one
! rsf_mesh_* call over the mesh in QDYN's own variables V and theta.
!
!   QDYN's i_rns_law   rsf's form                  parameters
!   0 classic          RSF_FORM_CLASSIC            f0 = mu_star, V0 = v_star
!   1 cut-offs         RSF_FORM_CUTOFF             f0 = mu_star, v0 = V1, each state's vc = V2
!   2 regularized      RSF_FORM_REGULARIZED        f0 = mu_star, V0 = v_star (SEAS 2018)
!   3 CNS              not rate-and-state: QDYN's own friction_cns module serves it
!
!   QDYN's itheta_law  rsf's law
!   0 aging without    RSF_LAW_AGING_NO_HEALING (dθ/dt = −Vθ/Dc)
!     healing
!   1 aging            RSF_LAW_AGING
!   2 slip             RSF_LAW_SLIP
!
! The mesh is made in set_theta_star, which QDYN calls once its parameters are set (at
! initialisation, and in its unit tests after each change of law); it is made again if a call
! finds another law or mesh size than the mesh's (QDYN's unit tests switch itheta_law without
! calling set_theta_star). A host that changes a parameter array must call set_theta_star.
!
! V <= 0: QDYN integrates V itself, and a trial stage of its solvers can reach V <= 0, where
! rate-and-state friction is not defined. The mesh is made with RSF_DOMAIN_CONTINUE: there
! each closed form is evaluated as written at the signed V (a/V, b/theta, 1 - V theta/Dc, the
! regularized form's odd continuation), NaN where the formula is undefined (the log in the
! classic friction, the slip law's rate) — the numbers QDYN's own friction module returns, so
! both of QDYN's solvers take the same steps on rsf's friction as on their own. Any refusal by
! rsf (parameters out of range at set-up, a non-finite result at V > 0) stops the run with
! rsf's message naming the node.
module friction

  use iso_c_binding
  use rsf
  use problem_class, only : problem_type

  implicit none
  private

  public :: set_theta_star, friction_mu, dmu_dv_dtheta, dtheta_dt

  ! the mesh, and the laws and size it was made for
  type(c_ptr), save :: mesh = c_null_ptr
  integer, save :: mesh_rns_law = -1, mesh_theta_law = -1, mesh_nn = -1

contains

!--------------------------------------------------------------------------------------
! Makes the mesh from QDYN's laws and parameter arrays (table above).
subroutine make_mesh(pb)

  type(problem_type), intent(in) :: pb
  type(RsfFrictionParams), dimension(:), allocatable :: fp
  type(RsfStateParams), dimension(:), allocatable :: sp
  integer(c_int32_t) :: form, law
  integer(c_int) :: st
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
    return ! CNS: QDYN's own friction_cns module serves it
  case default
    stop 'friction (rsf): unknown friction law type'
  end select
  select case (pb%itheta_law)
  case (0)
    law = RSF_LAW_AGING_NO_HEALING
  case (1)
    law = RSF_LAW_AGING
  case (2)
    law = RSF_LAW_SLIP
  case default
    stop 'friction (rsf): unknown state evolution law type'
  end select
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
  call rsf_mesh_free(mesh)
  mesh = c_null_ptr
  st = rsf_mesh_new(int(n, c_size_t), fp, sp, RSF_DOMAIN_CONTINUE, mesh)
  call check(st, 'rsf_mesh_new')
  mesh_rns_law = pb%i_rns_law
  mesh_theta_law = pb%itheta_law
  mesh_nn = n

end subroutine make_mesh

!--------------------------------------------------------------------------------------
! The mesh for pb: made again when the laws or the size are not those it was made for.
subroutine ensure_mesh(pb)

  type(problem_type), intent(in) :: pb

  if (mesh_rns_law /= pb%i_rns_law .or. mesh_theta_law /= pb%itheta_law .or. mesh_nn /= pb%mesh%nn &
      .or. .not. c_associated(mesh)) call make_mesh(pb)

end subroutine ensure_mesh

!--------------------------------------------------------------------------------------
! Stops the run with rsf's message when a call failed.
subroutine check(st, call_name)

  integer(c_int), intent(in) :: st
  character(len=*), intent(in) :: call_name

  if (st /= RSF_OK) then
    write (0, '(a,a,a,i0,a,a)') ' friction (rsf): ', call_name, ' returned ', st, ': ', rsf_error_message()
    stop 'friction (rsf): rsf refused the evaluation'
  end if

end subroutine check

!--------------------------------------------------------------------------------------
! QDYN's normalisation of θ, kept for QDYN's other modules (rsf does not use it): Dc/V* for
! the classic and regularized laws, Dc/V2 with cut-offs, 1 for CNS. QDYN calls this once its
! parameters are set, so the mesh is made here.
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
  call make_mesh(pb)

end subroutine set_theta_star

!--------------------------------------------------------------------------------------
function friction_mu(v, theta, pb) result(mu)

  type(problem_type), intent(in) :: pb
  double precision, dimension(pb%mesh%nn), intent(in) :: v, theta
  double precision, dimension(pb%mesh%nn) :: mu

  if (pb%i_rns_law == 3) then
    write (6, *) "friction.f90::friction_mu is deprecated for the CNS model"
    stop
  end if
  call ensure_mesh(pb)
  call check(rsf_mesh_friction(mesh, int(pb%mesh%nn, c_size_t), v, theta, mu), 'rsf_mesh_friction')

end function friction_mu

!--------------------------------------------------------------------------------------
subroutine dtheta_dt(v, tau, sigma, theta, theta2, dth_dt, dth2_dt, pb)

  use friction_cns, only : dphi_dt

  type(problem_type), intent(in) :: pb
  double precision, dimension(pb%mesh%nn), intent(in) :: v, tau, sigma
  double precision, dimension(pb%mesh%nn), intent(in) :: theta, theta2
  double precision, dimension(pb%mesh%nn) :: dth_dt, dth2_dt

  if (pb%i_rns_law == 3) then
    ! CNS: porosity and its rate come from QDYN's own CNS module
    call dphi_dt(v, tau, sigma, theta, theta2, dth_dt, dth2_dt, pb)
  else
    call ensure_mesh(pb)
    call check(rsf_mesh_state_rate(mesh, int(pb%mesh%nn, c_size_t), v, theta, dth_dt), 'rsf_mesh_state_rate')
  end if

end subroutine dtheta_dt

!--------------------------------------------------------------------------------------
subroutine dmu_dv_dtheta(dmu_dv, dmu_dtheta, v, theta, pb)

  type(problem_type), intent(in) :: pb
  double precision, dimension(pb%mesh%nn), intent(in) :: v, theta
  double precision, dimension(pb%mesh%nn), intent(out) :: dmu_dv, dmu_dtheta

  if (pb%i_rns_law == 3) then
    write (6, *) "friction.f90::dmu_dv_dtheta is deprecated for the CNS model"
    stop
  end if
  call ensure_mesh(pb)
  call check(rsf_mesh_partials(mesh, int(pb%mesh%nn, c_size_t), v, theta, dmu_dv, dmu_dtheta), 'rsf_mesh_partials')

end subroutine dmu_dv_dtheta

end module friction
