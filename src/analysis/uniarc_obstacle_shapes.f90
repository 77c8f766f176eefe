!> The gaps of curved and broken obstacle surfaces: an ellipse (an oval host pipe, a cavity or a
!> cylinder) and a polyline (steps, trenches), with the derivatives the contact rows need.
!>
!> Each gap is the signed distance from the node's current position x to the surface, positive on the
!> free side, so that its gradient is the unit normal at the nearest point of the surface (pointing to
!> the free side) and its Hessian the change of that normal along the surface. For a curve of signed
!> curvature κ at the nearest point (κ > 0 when the curve bends toward the free side, i.e. its centre of
!> curvature is on the free side) and unit tangent t there, the signed distance g has
!>
!>   ∂g/∂x = n,   ∂²g/∂x² = −κ/(1 − κ g) t tᵀ
!>
!> (the Hessian of the distance function in principal coordinates: Gilbarg & Trudinger 2001, Elliptic
!> Partial Differential Equations of Second Order, §14.6, Lemma 14.17; docs/theory.md §3.7). The circle
!> of radius R is κ = 1/R inside (g = R − |x − c|) and κ = −1/R outside; a straight segment κ = 0; a
!> corner point of a polyline is a circle of radius 0.
!>
!> All routines are pure and allocation-free: the contact assembly calls them at every iteration.
module uniarc_obstacle_shapes
   use uniarc_kinds, only: dp
   implicit none
   private
   public :: ellipse_gap, ellipse_closest_point, polyline_gap, polyline_concave_corner

   !> Newton iterations of the ellipse's closest point: it converges monotonically (see
   !> ellipse_closest_point), quadratically near the root; 200 is far above what any point needs.
   integer, parameter :: max_newton = 200

contains

   !> Gap g, gradient a = ∂g/∂x (2) and Hessian h (2×2) of the point x against the ellipse of centre
   !> `centre`, semi-axis a = semi_axes(1) along the unit direction `axis` and b = semi_axes(2) across it
   !> (a, b > 0; either may be the larger). `inside` true: the free side is inside the ellipse (a cavity,
   !> g = −ρ); false: outside (a rigid oval cylinder, g = ρ), ρ the signed distance, positive outside.
   !> The nearest point comes from ellipse_closest_point; with a = b the results are those of the
   !> circle to round-off.
   pure subroutine ellipse_gap(centre, axis, semi_axes, x, inside, gap, gradient, hessian)
      real(dp), intent(in) :: centre(2), axis(2), semi_axes(2), x(2)
      logical, intent(in) :: inside
      real(dp), intent(out) :: gap, gradient(2), hessian(2, 2)
      real(dp) :: d(2), p(2), y(2), z(2), normal(2), n(2), t(2), a, b, rho, kappa, q, factor
      logical :: swapped

      d = x - centre
      ! local coordinates along (a, b), then reflected so that the larger semi-axis is the first
      p = [axis(1)*d(1) + axis(2)*d(2), -axis(2)*d(1) + axis(1)*d(2)]
      a = semi_axes(1)
      b = semi_axes(2)
      swapped = a < b
      if (swapped) then
         p = [p(2), p(1)]
         a = semi_axes(2)
         b = semi_axes(1)
      end if
      y = abs(p)
      call ellipse_closest_point(a, b, y, z)
      normal = [z(1)/a**2, z(2)/b**2]
      q = norm2(normal)
      normal = normal/q
      rho = dot_product(normal, y - z)
      ! κ = 1/(a² b² (z1²/a⁴ + z2²/b⁴)^(3/2)): the curvature at z, centre of curvature inside
      kappa = 1.0_dp/(a**2*b**2*q**3)
      ! back to the quadrant of p, through the reflection, to global axes
      normal = sign(1.0_dp, p)*normal
      if (swapped) normal = [normal(2), normal(1)]
      n = [axis(1)*normal(1) - axis(2)*normal(2), axis(2)*normal(1) + axis(1)*normal(2)]
      t = [-n(2), n(1)]
      ! At the centre of curvature (1 + κρ = 0, a point of the evolute, far inside the cavity) the
      ! distance has no second derivative; its Hessian enters the tangent only times the reaction,
      ! which is zero that far from the wall: the curvature term is dropped there (no 0/0 or x/0).
      if (abs(1.0_dp + kappa*rho) > sqrt(epsilon(1.0_dp))) then
         factor = kappa/(1.0_dp + kappa*rho)
      else
         factor = 0.0_dp
      end if
      hessian = factor*reshape([t(1)*t(1), t(2)*t(1), t(1)*t(2), t(2)*t(2)], [2, 2])
      if (inside) then
         gap = -rho
         gradient = -n
         hessian = -hessian
      else
         gap = rho
         gradient = n
      end if
   end subroutine ellipse_gap

   !> The point z of the ellipse x²/a² + y²/b² = 1 (a ≥ b > 0) nearest to the point y of the first
   !> quadrant (y(1), y(2) ≥ 0); z is in the first quadrant too.
   !>
   !> After Eberly (2011, "Distance from a Point to an Ellipse, an Ellipsoid, or a Hyperellipsoid",
   !> Geometric Tools): the nearest point is z = (a² y1/(t + a²), b² y2/(t + b²)), t the root of
   !> F(t) = (a y1/(t + a²))² + (b y2/(t + b²))² − 1 on t > −b². F is decreasing and convex there, and
   !> F(t0) ≥ 0 at t0 = −b² + b y2, so Newton's method from t0 stays left of the root and increases to it
   !> monotonically (Fourier's condition): no bracketing failure, no overshoot; it is run in s = t + b²
   !> so that no cancellation spoils t + b² near the centre. Eberly bisects; Newton is the same safe
   !> iteration, faster. On the major axis (y2 = 0) the nearest point is
   !> (a² y1/(a² − b²), b √(1 − (z1/a)²)) while y1 < (a² − b²)/a, else (a, 0); on the minor axis (0, b).
   pure subroutine ellipse_closest_point(a, b, y, z)
      real(dp), intent(in) :: a, b, y(2)
      real(dp), intent(out) :: z(2)
      real(dp) :: s, s_next, s_high, c, r1, r2, f, slope
      integer :: iteration

      if (y(2) > 0.0_dp) then
         if (y(1) > 0.0_dp) then
            ! Newton in s = t + b² (exact at the start, s0 = b y2): t + b² and t + a² = s + (a² − b²) keep
            ! their relative precision even when s is tiny (a point near the centre or the major axis).
            c = a**2 - b**2
            s = b*y(2)
            s_high = sqrt((a*y(1))**2 + (b*y(2))**2)
            do iteration = 1, max_newton
               r1 = a*y(1)/(s + c)
               r2 = b*y(2)/s
               f = r1**2 + r2**2 - 1.0_dp
               if (.not. f > 0.0_dp) exit
               slope = -2.0_dp*(r1**2/(s + c) + r2**2/s)
               s_next = min(s - f/slope, s_high)
               if (.not. s_next > s) exit
               s = s_next
            end do
            z = [a**2*y(1)/(s + c), b**2*y(2)/s]
         else
            z = [0.0_dp, b]
         end if
      else
         if (y(1) < (a**2 - b**2)/a) then
            z(1) = a**2*y(1)/(a**2 - b**2)
            z(2) = b*sqrt(max(0.0_dp, 1.0_dp - (z(1)/a)**2))
         else
            z = [a, 0.0_dp]
         end if
      end if
   end subroutine ellipse_closest_point

   !> Gap g, gradient a = ∂g/∂x (2) and Hessian h (2×2) of the point x against the polyline through
   !> `vertices` (2, n ≥ 2), whose first and last segments go on as rays; the free side is on the left
   !> of the direction vertex 1 → vertex n.
   !>
   !> g is the signed distance to the nearest feature: a segment (g = n·(x − p), a = n its left unit
   !> normal, h = 0) or an inner vertex v (g = ±|x − v|, a = ±e with e = (x − v)/|x − v|,
   !> h = ±(I − e eᵀ)/|x − v|, a circle of radius 0), the sign that of (x − v)·(n_before + n_after), the
   !> vertex's pseudo-normal (Bærentzen & Aanæs 2005, IEEE Trans. Vis. Comput. Graph. 11:243–253). A
   !> point as near to a segment as to a vertex takes the segment. Consecutive segments must not fold back
   !> on each other (the deck checks), and no segment has zero length.
   pure subroutine polyline_gap(vertices, x, gap, gradient, hessian)
      real(dp), intent(in) :: vertices(:, :)
      real(dp), intent(in) :: x(2)
      real(dp), intent(out) :: gap, gradient(2), hessian(2, 2)
      real(dp) :: d(2), t(2), n(2), s, length, distance, best_segment, best_vertex, signed, e(2), m(2), sgn
      integer :: k, n_vertices, vertex

      n_vertices = size(vertices, 2)
      best_segment = huge(1.0_dp)
      signed = 0.0_dp
      gradient = 0.0_dp
      do k = 1, n_vertices - 1
         d = vertices(:, k + 1) - vertices(:, k)
         length = norm2(d)
         t = d/length
         s = dot_product(x - vertices(:, k), t)
         if ((k > 1 .and. s < 0.0_dp) .or. (k < n_vertices - 1 .and. s > length)) cycle
         n = [-t(2), t(1)]
         distance = dot_product(x - vertices(:, k), n)
         if (abs(distance) < best_segment) then
            best_segment = abs(distance)
            signed = distance
            gradient = n
         end if
      end do
      best_vertex = huge(1.0_dp)
      vertex = 0
      do k = 2, n_vertices - 1
         distance = norm2(x - vertices(:, k))
         if (distance < best_vertex) then
            best_vertex = distance
            vertex = k
         end if
      end do

      hessian = 0.0_dp
      if (vertex == 0 .or. .not. best_vertex < best_segment) then
         gap = signed
         return
      end if
      m = left_normal(vertices(:, vertex - 1), vertices(:, vertex)) + &
          left_normal(vertices(:, vertex), vertices(:, vertex + 1))
      e = x - vertices(:, vertex)
      if (.not. best_vertex > 0.0_dp) then
         gap = 0.0_dp
         gradient = m/norm2(m)
         return
      end if
      e = e/best_vertex
      sgn = sign(1.0_dp, dot_product(e, m))
      gap = sgn*best_vertex
      gradient = sgn*e
      hessian = (sgn/best_vertex)*reshape([1.0_dp - e(1)**2, -e(1)*e(2), -e(1)*e(2), 1.0_dp - e(2)**2], [2, 2])
   end subroutine polyline_gap

   !> The inner vertex of the polyline `vertices` (2, n; free side on the left of 1 → n) that is a
   !> concave corner of the free side (the polyline turns left there: the free side is the inside of
   !> the corner, a trench or the inside of an L) and lies within `reach` of the point x; 0 if none.
   !> There the gap of polyline_gap is the distance to the nearer of the two faces: it is continuous
   !> but not differentiable on the corner's bisector (its gradient jumps from one face's normal to the
   !> other's), so a node in contact at the corner has no Newton iteration that settles.
   pure integer function polyline_concave_corner(vertices, x, reach) result(corner)
      real(dp), intent(in) :: vertices(:, :)
      real(dp), intent(in) :: x(2), reach
      real(dp) :: before(2), after(2), nearest
      integer :: k
      corner = 0
      nearest = huge(1.0_dp)
      do k = 2, size(vertices, 2) - 1
         before = vertices(:, k) - vertices(:, k - 1)
         after = vertices(:, k + 1) - vertices(:, k)
         if (.not. before(1)*after(2) - before(2)*after(1) > 0.0_dp) cycle   ! a right turn: convex
         if (norm2(x - vertices(:, k)) > min(reach, nearest)) cycle
         nearest = norm2(x - vertices(:, k))
         corner = k
      end do
   end function polyline_concave_corner

   !> Left unit normal of the segment p → q (its direction turned by +90°).
   pure function left_normal(p, q) result(n)
      real(dp), intent(in) :: p(2), q(2)
      real(dp) :: n(2)
      real(dp) :: d(2)
      d = (q - p)/norm2(q - p)
      n = [-d(2), d(1)]
   end function left_normal

end module uniarc_obstacle_shapes
