"""Security headers every response carries: the Content-Security-Policy (``CONTINUUM_CSP`` in the settings).

HSTS, ``nosniff``, the referrer policy and the frame options are Django's (``SecurityMiddleware``,
``XFrameOptionsMiddleware``), driven by the settings' ``CONTINUUM_HTTPS`` block.
"""

from __future__ import annotations

from django.conf import settings


def policy_for(path: str) -> str:
    """The policy of a page: the settings' one, with inline style elements allowed on the few pages whose
    vendored code needs them (``CONTINUUM_CSP_INLINE_STYLE_PATHS``)."""
    policy = settings.CONTINUUM_CSP
    if any(path.startswith(p) for p in getattr(settings, "CONTINUUM_CSP_INLINE_STYLE_PATHS", ())):
        policy = policy.replace("style-src 'self'", "style-src 'self' 'unsafe-inline'", 1)
    return policy


class ContentSecurityPolicyMiddleware:
    def __init__(self, get_response):
        self.get_response = get_response

    def __call__(self, request):
        response = self.get_response(request)
        if settings.CONTINUUM_CSP and "Content-Security-Policy" not in response:
            response["Content-Security-Policy"] = policy_for(request.path)
        return response
