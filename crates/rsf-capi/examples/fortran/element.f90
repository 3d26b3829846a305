! A host code in Fortran calling rsf through iso_c_binding: the friction, state rate and
! slip-rate solve of the BP1-QD surface element, checked against closed forms, and the batch
! call over an array of elements. Build (the test does this):
!   gfortran element.f90 ../../../../target/release/librsf_capi.a -lpthread -ldl -lm
module rsf
  use iso_c_binding
  implicit none
  integer(c_int), parameter :: RSF_OK = 0, RSF_FORM_REGULARIZED = 1, RSF_LAW_AGING = 0
  integer(c_int32_t), parameter :: RSF_ABI_VERSION = 1
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
  end interface
end module

program element
  use rsf
  implicit none
  type(RsfFrictionParams) :: fp, fps(3)
  type(RsfStateParams) :: sp, sps(3)
  real(c_double) :: psi, f, fx, fpsi, rate, lnv, lnth, tau, ss, lv(3), th(3), ta(3), sg(3), et(3)
  integer(c_int) :: st, its, i
  real(c_double), parameter :: vp = 1d-9, sigma = 50d6, eta = 2670d0 * 3464d0 / 2d0
  fp = RsfFrictionParams(RSF_ABI_VERSION, RSF_FORM_REGULARIZED, 0.6d0, 0.010d0, 1d-6)
  sp = RsfStateParams(RSF_ABI_VERSION, RSF_LAW_AGING, 0.015d0, 0.008d0, 0d0)
  ! steady state at Vp: theta = Dc/Vp, friction = f0 + (a - b) ln(Vp/V0), d ln theta/dt = 0
  lnth = log(0.008d0 / vp)
  st = rsf_psi(sp, 1d-6, lnth, psi)
  st = rsf_friction(fp, log(vp), psi, f, fx, fpsi)
  ss = 0.6d0 + (0.010d0 - 0.015d0) * log(vp / 1d-6)
  st = rsf_ln_theta_rate(sp, log(vp), lnth, rate)
  print '(a,es12.4)', 'friction error ', abs(f - ss)
  print '(a,es12.4)', 'rate at steady state ', abs(rate)
  ! the slip rate balancing sigma f + eta Vp is Vp
  tau = sigma * f + eta * vp
  st = rsf_solve_slip_rate(fp, psi, tau, sigma, eta, log(vp) + 0.1d0, lnv, its)
  print '(a,es12.4,a,i0)', 'solve error ', abs(lnv - log(vp)), ' iterations ', its
  ! three elements at once
  do i = 1, 3
    fps(i) = fp
    sps(i) = sp
    th(i) = lnth
    sg(i) = sigma
    et(i) = eta
    ta(i) = tau * (1d0 + 1d-3 * i)
    lv(i) = log(vp)
  end do
  st = rsf_batch_solve_slip_rate(3_c_size_t, fps, sps, th, ta, sg, et, lv)
  print '(a,i0,a,3es12.4)', 'batch status ', st, ' V ', exp(lv)
  if (st /= RSF_OK .or. .not. (exp(lv(1)) > vp .and. exp(lv(3)) > exp(lv(2)))) stop 1
end program
