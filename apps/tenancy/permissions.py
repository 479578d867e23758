"""What a fleet token may do, by its scope.

"operator" tokens may do everything their fleet may. "robot" tokens read everything of their fleet and
write only where a view says robots write: its ``robot_actions`` names the viewset actions (e.g.
``{"create"}`` on the report endpoint) or, for a plain APIView, the HTTP methods in lower case. Session
users (operators in a browser) are not concerned. The host permission knows no domain app: the views
declare themselves.
"""

from rest_framework import permissions

from .models import FleetToken


def robot_may(view, request) -> bool:
    allowed = getattr(view, "robot_actions", ())
    return getattr(view, "action", None) in allowed or request.method.lower() in allowed


class TokenScopePermission(permissions.BasePermission):
    message = "this token's scope is robot: it may read its fleet and post reports and events, not change it"

    def has_permission(self, request, view) -> bool:
        token = request.auth
        if not isinstance(token, FleetToken) or token.scope == FleetToken.Scope.OPERATOR:
            return True
        return request.method in permissions.SAFE_METHODS or robot_may(view, request)
