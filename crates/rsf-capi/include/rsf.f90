! rsf's C ABI for Fortran hosts (iso_c_binding): the parameter structs, the ids and every
! function of include/rsf.h, one module. Compile it with the host and link librsf_capi.a:
!   gfortran -c rsf.f90 && gfortran host.f90 rsf.o librsf_capi.a -lpthread -ldl -lm
! Variables are logs (ln V, ln θ), but for a mesh's calls (rsf_mesh_*), which take V and θ;
! every function returns an RsfStatus (RSF_OK = 0) and
! rsf_last_error gives the calling thread's last message (a C string).
module rsf
  use iso_c_binding
  implicit none
  integer(c_int32_t), parameter :: RSF_ABI_VERSION = 1
  ! RsfStatus
  integer(c_int), parameter :: RSF_OK = 0, RSF_BAD_INPUT = 1, RSF_UNKNOWN_ID = 2, RSF_NO_ROOT = 3, &
    RSF_NOT_CONVERGED = 4, RSF_INTERNAL = 5
  ! RsfForm: classic, regularized (SEAS), cut-off velocities (v0 holds V1, each state's vc its V2)
  integer(c_int32_t), parameter :: RSF_FORM_CLASSIC = 0, RSF_FORM_REGULARIZED = 1, RSF_FORM_CUTOFF = 2
  ! RsfLaw
  integer(c_int32_t), parameter :: RSF_LAW_AGING = 0, RSF_LAW_SLIP = 1, RSF_LAW_KATO_TULLIS = 2, RSF_LAW_PRZ = 3, &
    RSF_LAW_AGING_NO_HEALING = 6
  ! RsfDomain: what a mesh's calls do at V <= 0 or theta <= 0
  integer(c_int32_t), parameter :: RSF_DOMAIN_REFUSE = 0, RSF_DOMAIN_CONTINUE = 1
  type, bind(c) :: RsfFrictionParams
    integer(c_int32_t) :: version
    integer(c_int32_t) :: form
    real(c_double) :: f0, a, v0
  end type
  type, bind(c) :: RsfStateParams
    integer(c_int32_t) :: version
    integer(c_int32_t) :: law
    real(c_double) :: b, dc, vc
  end type
  interface
    ! (Fortran names are case-blind: RSF_ABI_VERSION above is the header's constant, this is
    ! the library's rsf_abi_version())
    function rsf_library_abi_version() bind(c, name="rsf_abi_version") result(v)
      import
      integer(c_int32_t) :: v
    end function
    function rsf_last_error() bind(c, name="rsf_last_error") result(msg)
      import
      type(c_ptr) :: msg
    end function
    function rsf_friction(p, ln_v, psi, f, fx, fpsi) bind(c, name="rsf_friction") result(st)
      import
      type(RsfFrictionParams), intent(in) :: p
      real(c_double), value :: ln_v, psi
      real(c_double), intent(out) :: f, fx, fpsi
      integer(c_int) :: st
    end function
    function rsf_psi(s, v0, ln_theta, psi) bind(c, name="rsf_psi") result(st)
      import
      type(RsfStateParams), intent(in) :: s
      real(c_double), value :: v0, ln_theta
      real(c_double), intent(out) :: psi
      integer(c_int) :: st
    end function
    function rsf_state_term(p, s, ln_theta, psi, dpsi) bind(c, name="rsf_state_term") result(st)
      import
      type(RsfFrictionParams), intent(in) :: p
      type(RsfStateParams), intent(in) :: s
      real(c_double), value :: ln_theta
      real(c_double), intent(out) :: psi, dpsi
      integer(c_int) :: st
    end function
    function rsf_ln_theta_rate(s, ln_v, ln_theta, rate) bind(c, name="rsf_ln_theta_rate") result(st)
      import
      type(RsfStateParams), intent(in) :: s
      real(c_double), value :: ln_v, ln_theta
      real(c_double), intent(out) :: rate
      integer(c_int) :: st
    end function
    function rsf_solve_slip_rate(p, psi, tau, sigma, eta, guess, ln_v, its) &
        bind(c, name="rsf_solve_slip_rate") result(st)
      import
      type(RsfFrictionParams), intent(in) :: p
      real(c_double), value :: psi, tau, sigma, eta, guess
      real(c_double), intent(out) :: ln_v
      integer(c_int), intent(out) :: its
      integer(c_int) :: st
    end function
    function rsf_batch_rates(n, fp, sp, ln_v, ln_theta, f, fx, fpsi, rate) &
        bind(c, name="rsf_batch_rates") result(st)
      import
      integer(c_size_t), value :: n
      type(RsfFrictionParams), intent(in) :: fp(*)
      type(RsfStateParams), intent(in) :: sp(*)
      real(c_double), intent(in) :: ln_v(*), ln_theta(*)
      real(c_double), intent(out) :: f(*), fx(*), fpsi(*), rate(*)
      integer(c_int) :: st
    end function
    function rsf_batch_partials(n, fp, sp, ln_v, ln_theta, f, fx, fz, rate) &
        bind(c, name="rsf_batch_partials") result(st)
      import
      integer(c_size_t), value :: n
      type(RsfFrictionParams), intent(in) :: fp(*)
      type(RsfStateParams), intent(in) :: sp(*)
      real(c_double), intent(in) :: ln_v(*), ln_theta(*)
      real(c_double), intent(out) :: f(*), fx(*), fz(*), rate(*)
      integer(c_int) :: st
    end function
    function rsf_batch_solve_slip_rate(n, fp, sp, ln_theta, tau, sigma, eta, ln_v) &
        bind(c, name="rsf_batch_solve_slip_rate") result(st)
      import
      integer(c_size_t), value :: n
      type(RsfFrictionParams), intent(in) :: fp(*)
      type(RsfStateParams), intent(in) :: sp(*)
      real(c_double), intent(in) :: ln_theta(*), tau(*), sigma(*), eta(*)
      real(c_double), intent(inout) :: ln_v(*)
      integer(c_int) :: st
    end function
    ! a mesh: parameters checked once (rsf_mesh_new), then evaluations in V and theta
    function rsf_mesh_new(n, fp, sp, domain, mesh) bind(c, name="rsf_mesh_new") result(st)
      import
      integer(c_size_t), value :: n
      type(RsfFrictionParams), intent(in) :: fp(*)
      type(RsfStateParams), intent(in) :: sp(*)
      integer(c_int32_t), value :: domain
      type(c_ptr), intent(out) :: mesh
      integer(c_int) :: st
    end function
    subroutine rsf_mesh_free(mesh) bind(c, name="rsf_mesh_free")
      import
      type(c_ptr), value :: mesh
    end subroutine
    function rsf_mesh_friction(mesh, n, v, theta, mu) bind(c, name="rsf_mesh_friction") result(st)
      import
      type(c_ptr), value :: mesh
      integer(c_size_t), value :: n
      real(c_double), intent(in) :: v(*), theta(*)
      real(c_double), intent(out) :: mu(*)
      integer(c_int) :: st
    end function
    function rsf_mesh_partials(mesh, n, v, theta, dmu_dv, dmu_dtheta) bind(c, name="rsf_mesh_partials") result(st)
      import
      type(c_ptr), value :: mesh
      integer(c_size_t), value :: n
      real(c_double), intent(in) :: v(*), theta(*)
      real(c_double), intent(out) :: dmu_dv(*), dmu_dtheta(*)
      integer(c_int) :: st
    end function
    function rsf_mesh_state_rate(mesh, n, v, theta, dtheta_dt) bind(c, name="rsf_mesh_state_rate") result(st)
      import
      type(c_ptr), value :: mesh
      integer(c_size_t), value :: n
      real(c_double), intent(in) :: v(*), theta(*)
      real(c_double), intent(out) :: dtheta_dt(*)
      integer(c_int) :: st
    end function
  end interface
contains
  ! The calling thread's last failure message as a Fortran string.
  function rsf_error_message() result(msg)
    character(len=:), allocatable :: msg
    character(kind=c_char), pointer :: chars(:)
    interface
      function strlen(s) bind(c, name="strlen") result(n)
        import
        type(c_ptr), value :: s
        integer(c_size_t) :: n
      end function
    end interface
    type(c_ptr) :: p
    integer :: i, n
    p = rsf_last_error()
    n = int(strlen(p))
    call c_f_pointer(p, chars, [n])
    allocate(character(len=n) :: msg)
    do i = 1, n
      msg(i:i) = chars(i)
    end do
  end function
end module
